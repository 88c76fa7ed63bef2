#include "emulator/replay/log_stream.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "transport/posix/errors.hpp"
#include "transport/posix/fd.hpp"

namespace gpsemu::replay {

using std::chrono::nanoseconds;

namespace {

constexpr nanoseconds kDay = std::chrono::hours(24);
constexpr nanoseconds kHalfDay = std::chrono::hours(12);

/// Talker + type, e.g. "GPGGA" (an epoch holds each time-bearing address once).
std::string address(const nmea::Sentence& s) { return s.talker + s.type; }

/// The epoch being assembled. Past kMaxEpochSentences or kMaxEpochBytes it is oversized: its
/// sentences are let go and only counted, so memory stays bounded whatever the log holds.
struct Builder {
  LogEpoch epoch;
  std::vector<std::string> addresses;  ///< distinct addresses seen in the epoch
  bool empty_time_field = false;  ///< holds a time-bearing sentence whose time is empty
  std::uint64_t sentences = 0;    ///< sentences given to the epoch, kept or not

  [[nodiscard]] bool empty() const { return sentences == 0; }
  [[nodiscard]] bool oversized() const { return sentences > epoch.sentences.size(); }
  [[nodiscard]] bool has(const std::string& a) const {
    return std::find(addresses.begin(), addresses.end(), a) != addresses.end();
  }
  void add(LogSentence s) {
    if (std::string a = address(s.parsed); !has(a)) addresses.push_back(std::move(a));
    ++sentences;
    if (sentences > kMaxEpochSentences || epoch.bytes.size() + s.raw.size() > kMaxEpochBytes) {
      epoch.sentences = {};  // oversized: kept no longer
      epoch.bytes = {};
      return;
    }
    epoch.bytes += s.raw;
    epoch.sentences.push_back(std::move(s));
  }
};

/// A time of day on the log's timeline: a day added when it goes back by more than 12 h
/// (midnight), taken off when it goes forward by more than 12 h (back across midnight).
struct DayClock {
  std::int64_t day = 0;
  std::optional<nanoseconds> previous;

  nanoseconds place(nanoseconds tod, LogCounts* counts) {
    if (previous) {
      if (tod < *previous - kHalfDay) {
        ++day;
        if (counts) ++counts->rollovers;
      } else if (tod > *previous + kHalfDay) {
        --day;
        if (counts) ++counts->steps_back;
      } else if (tod < *previous) {
        if (counts) ++counts->steps_back;
      }
    }
    previous = tod;
    return day * kDay + tod;
  }
};

}  // namespace

/// Bytes to epochs, incrementally (rules in replay_log.hpp): each good sentence keeps its recorded
/// bytes, from its '$' to its line ending (a CR waits for the next byte: CR LF is one ending).
class EpochSplitter {
 public:
  explicit EpochSplitter(LogCounts& counts) : counts_(counts) {}

  void feed(std::string_view chunk, std::deque<LogEpoch>& out) {
    for (const char c : chunk) {
      if (held_) {  // a sentence ended at CR: an LF right after is its line ending too
        const bool lf = c == '\n';
        if (lf) held_->raw += c;
        take(std::move(*held_), out);
        held_.reset();
        if (lf) {
          (void)reader_.feed(std::string_view(&c, 1));
          continue;
        }
      }
      if (c == '$') {
        raw_.assign(1, '$');
      } else if (raw_.size() <= nmea::max_parse_chars) {
        raw_ += c;  // past that no sentence can end here
      }
      auto done = reader_.feed(std::string_view(&c, 1));
      if (done.empty()) continue;
      LogSentence s;
      s.raw = raw_;
      s.parsed = std::move(done.front());
      if (c == '\r') {
        held_ = std::move(s);
      } else {
        take(std::move(s), out);
      }
    }
    counts_.stream = reader_.stats();
  }

  /// The end of the log: the last sentence (even without a line ending) and epoch.
  void finish(std::deque<LogEpoch>& out) {
    if (held_) take(std::move(*held_), out);
    held_.reset();
    if (auto last = reader_.finish()) {
      LogSentence s;
      s.raw = raw_;
      s.parsed = std::move(*last);
      take(std::move(s), out);
    }
    close(out);
    counts_.stream = reader_.stats();
  }

 private:
  void take(LogSentence s, std::deque<LogEpoch>& out) {
    const auto i = time_field_index(s.parsed);
    if (i && *i < s.parsed.fields.size() && !s.parsed.fields[*i].empty()) {
      s.time_of_day = parse_time_of_day(s.parsed.fields[*i]);
      if (!s.time_of_day) ++counts_.bad_time_fields;
    }
    if (s.time_of_day) {
      const auto tod = *s.time_of_day;
      if (current_.empty()) {
        current_.epoch.time_of_day = tod;
      } else if (current_.epoch.time_of_day) {
        if (*current_.epoch.time_of_day != tod) {
          close(out);
          current_.epoch.time_of_day = tod;
        }
      } else if (current_.empty_time_field) {
        close(out);  // a no-time epoch, then the first timed one
        current_.epoch.time_of_day = tod;
      } else {
        current_.epoch.time_of_day = tod;  // leading GSA/GSV... belong to this epoch
      }
    } else if (i) {
      if (current_.has(address(s.parsed))) close(out);
      current_.empty_time_field = true;
    }
    current_.add(std::move(s));
  }

  void close(std::deque<LogEpoch>& out) {
    if (current_.oversized()) {
      ++counts_.oversized_epochs;
      counts_.oversized_sentences += current_.sentences;
    } else if (!current_.empty()) {
      out.push_back(std::move(current_.epoch));
    }
    current_ = Builder{};
  }

  LogCounts& counts_;
  nmea::StreamReader reader_;
  std::string raw_;  ///< bytes since the last '$' (at most max_parse_chars + 1)
  std::optional<LogSentence> held_;
  Builder current_;
};

/// Where the bytes come from: a file (read at an offset when regular, in order when a pipe) or memory.
struct LogStream::Source {
  posix::UniqueFd fd;
  std::string_view memory;
  bool is_memory = false;

  /// Up to `n` bytes at `offset` (a pipe: its next bytes); 0 at the end. Throws on a read error.
  std::size_t read(std::uint64_t offset, bool seekable, char* buffer, std::size_t n, const std::string& name) const {
    if (is_memory) {
      if (offset >= memory.size()) return 0;
      const std::size_t k = std::min<std::size_t>(n, memory.size() - offset);
      std::memcpy(buffer, memory.data() + offset, k);
      return k;
    }
    for (;;) {
      const ssize_t k = seekable ? ::pread(fd.get(), buffer, n, static_cast<off_t>(offset)) : ::read(fd.get(), buffer, n);
      if (k >= 0) return static_cast<std::size_t>(k);
      if (errno != EINTR) throw std::runtime_error(fmt::format("cannot read NMEA log '{}': {}", name, posix::errno_text(errno)));
    }
  }
};

namespace {

/// The timed epochs' first time and spacings, as epochs come (header comment of log_stream.hpp).
struct PeriodScan {
  DayClock clock;
  std::uint64_t untimed_before_first = 0;
  std::optional<nanoseconds> first_timed;
  std::optional<nanoseconds> previous;
  std::vector<nanoseconds> spacings;

  void add(const LogEpoch& e) {
    if (!e.time_of_day) {
      if (!first_timed) ++untimed_before_first;
      return;
    }
    const nanoseconds t = clock.place(*e.time_of_day, nullptr);
    if (!first_timed) first_timed = t;
    if (previous && t > *previous && spacings.size() < kPeriodSpacings) spacings.push_back(t - *previous);
    previous = t;
  }
  [[nodiscard]] bool done() const { return first_timed && spacings.size() >= kPeriodSpacings; }
  /// The lower median of the spacings; 1 s when there is none.
  [[nodiscard]] nanoseconds median() const {
    if (spacings.empty()) return std::chrono::seconds(1);
    std::vector<nanoseconds> v = spacings;
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>((v.size() - 1) / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
  }
};

}  // namespace

LogStream::LogStream(const std::filesystem::path& path) : name_(path.string()), source_(std::make_unique<Source>()) {
  source_->fd.reset(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY));
  if (source_->fd.get() < 0) {
    throw std::runtime_error(fmt::format("cannot open NMEA log '{}': {}", name_, posix::errno_text(errno)));
  }
  struct stat st {};
  if (::fstat(source_->fd.get(), &st) != 0) {
    throw std::runtime_error(fmt::format("cannot read NMEA log '{}': {}", name_, posix::errno_text(errno)));
  }
  if (S_ISDIR(st.st_mode)) throw std::runtime_error(fmt::format("cannot read NMEA log '{}': it is a directory", name_));
  seekable_ = S_ISREG(st.st_mode);
  start();
  if (window_.empty() && pass_.counts.oversized_epochs > 0) {
    const LogCounts& n = pass_.counts;
    throw std::runtime_error(fmt::format(
        "NMEA log '{}' has no epoch to send: {} oversized epochs ({} sentences) skipped; an epoch may have at most {} "
        "sentences and {} bytes", name_, n.oversized_epochs, n.oversized_sentences, kMaxEpochSentences, kMaxEpochBytes));
  }
  if (window_.empty()) {
    const auto& s = pass_.counts.stream;
    throw std::runtime_error(fmt::format(
        "NMEA log '{}' holds no valid NMEA sentence ({} bytes: {} bad checksums, {} malformed, {} binary/garbage "
        "bytes, {} comment lines)", name_, pass_.bytes, s.bad_checksum, s.malformed, s.garbage_bytes, s.comment_lines));
  }
}

LogStream::LogStream(std::string_view bytes, std::string name) : name_(std::move(name)), source_(std::make_unique<Source>()) {
  source_->memory = bytes;
  source_->is_memory = true;
  seekable_ = true;
  start();
}

LogStream::~LogStream() = default;

void LogStream::start() {
  splitter_ = std::make_unique<EpochSplitter>(pass_.counts);
  settle_timeline();
  fill();
}

bool LogStream::window_full() const {
  return window_.size() + cut_.size() >= kLookAheadEpochs || window_bytes_ >= kLookAheadBytes;
}

bool LogStream::read_chunk() {
  if (pass_.ended) return false;
  chunk_.resize(kReadChunkBytes);
  const std::size_t n = source_->read(offset_, seekable_, chunk_.data(), chunk_.size(), name_);
  offset_ += n;
  pass_.bytes += n;
  const std::size_t before = cut_.size();
  if (n == 0) {
    splitter_->finish(cut_);
    pass_.ended = true;
  } else {
    splitter_->feed(std::string_view(chunk_.data(), n), cut_);
  }
  pass_.epochs += cut_.size() - before;
  return n != 0;
}

void LogStream::settle_timeline() {
  // The first window: read until it tells the period and the first timed epoch, or is full.
  PeriodScan scan;
  std::size_t scanned = 0, cut_bytes = 0;
  while (!scan.done() && cut_.size() < kLookAheadEpochs && cut_bytes < kLookAheadBytes && read_chunk()) {
    for (; scanned < cut_.size(); ++scanned) {
      scan.add(cut_[scanned]);
      cut_bytes += cut_[scanned].bytes.size();
    }
  }
  for (; scanned < cut_.size(); ++scanned) scan.add(cut_[scanned]);
  if (!scan.done() && !pass_.ended) {
    if (seekable_) {
      // A second reader from the start, keeping only the spacings.
      scan = PeriodScan{};
      LogCounts scratch;
      EpochSplitter splitter(scratch);
      std::deque<LogEpoch> epochs;
      std::string buffer(kReadChunkBytes, '\0');
      std::uint64_t offset = 0;
      while (!scan.done()) {
        const std::size_t n = source_->read(offset, true, buffer.data(), buffer.size(), name_);
        offset += n;
        if (n == 0) {
          splitter.finish(epochs);
        } else {
          splitter.feed(std::string_view(buffer.data(), n), epochs);
        }
        for (; !epochs.empty(); epochs.pop_front()) scan.add(epochs.front());
        if (n == 0) break;
      }
    } else if (!scan.first_timed && scan.untimed_before_first > 0) {
      throw std::runtime_error(fmt::format(
          "NMEA log '{}' is a pipe and its first {} epochs carry no time: they cannot be placed before the first "
          "timed one (give it as a regular file)", name_, cut_.size()));
    }
  }
  period_ = scan.median();
  period_spacings_ = scan.spacings.size();
  leading_untimed_ = scan.first_timed ? scan.untimed_before_first : 0;
  first_timed_log_time_ = scan.first_timed.value_or(nanoseconds::zero());
  settled_ = true;
  place_cut();
  if (!window_.empty()) first_log_time_ = window_.front().log_time;
}

void LogStream::place_cut() {
  LogCounts& n = pass_.counts;
  for (; !cut_.empty(); cut_.pop_front()) {
    LogEpoch& e = cut_.front();
    if (e.time_of_day) {
      DayClock clock{day_, previous_tod_};
      e.log_time = clock.place(*e.time_of_day, &n);
      day_ = clock.day;
      previous_tod_ = clock.previous;
      if (previous_timed_) {
        const nanoseconds d = e.log_time - *previous_timed_;
        if (d * 2 > period_ * 3) {
          ++n.gaps;
          n.longest_gap = std::max(n.longest_gap, d);
        }
      }
      previous_timed_ = e.log_time;
    } else {
      ++n.untimed_epochs;
      if (leading_untimed_ > 0 && !previous_timed_) {
        e.log_time = first_timed_log_time_ - static_cast<std::int64_t>(leading_untimed_--) * period_;
      } else {
        e.log_time = previous_log_time_ ? *previous_log_time_ + period_ : nanoseconds::zero();
      }
    }
    previous_log_time_ = e.log_time;
    window_bytes_ += e.bytes.size();
    window_.push_back(std::move(e));
  }
}

void LogStream::fill() {
  while (!window_full() && read_chunk()) place_cut();
  place_cut();  // the last epochs at the end of the log
}

const LogEpoch* LogStream::peek() {
  if (window_.empty()) fill();
  return window_.empty() ? nullptr : &window_.front();
}

bool LogStream::pop(LogEpoch* epoch) {
  if (peek() == nullptr) return false;
  window_bytes_ -= window_.front().bytes.size();
  if (epoch) *epoch = std::move(window_.front());
  window_.pop_front();
  ++position_;
  if (!window_full()) fill();
  return true;
}

void LogStream::rewind() {
  if (!seekable_) throw std::logic_error("rewind of a log that is not a regular file");
  if (!first_pass_) first_pass_ = pass_;
  pass_ = Pass{};
  splitter_ = std::make_unique<EpochSplitter>(pass_.counts);
  window_.clear();
  cut_.clear();
  window_bytes_ = 0;
  offset_ = 0;
  position_ = 0;
  day_ = 0;
  previous_tod_.reset();
  previous_timed_.reset();
  previous_log_time_.reset();
  settle_timeline();  // the same first window: the same period and placement
  fill();
}

}  // namespace gpsemu::replay
