#include "transport/gpio_pps.hpp"

#include <fmt/format.h>
#include <gpiod.h>
#include <spdlog/spdlog.h>

#include <cerrno>
#include <charconv>
#include <stdexcept>

#include "transport/posix/errors.hpp"

namespace gpsemu::transport {

namespace {

constexpr const char* kConsumer = "gpsemu-pps";

std::string chip_failure(const std::string& chip, int err) {
  switch (err) {
    case ENOENT:
      return fmt::format("no GPIO chip '{}' on this machine (chips are /dev/gpiochip*; `gpiodetect` lists "
                         "them)", chip);
    case EACCES:
    case EPERM:
      return fmt::format("permission denied opening GPIO chip '{}' (add the user to the group owning "
                         "/dev/gpiochip*, usually 'gpio', or adjust the udev rule)", chip);
    case ENODEV:
    case ENOTTY:
    case EINVAL:
      return fmt::format("'{}' is not a GPIO character device", chip);
    default:
      return fmt::format("cannot open GPIO chip '{}': {}", chip, posix::errno_text(err));
  }
}

}  // namespace

GpioPps::GpioPps(const std::string& chip, const std::string& line, PpsPolarity polarity) : PpsLine(polarity) {
  const std::string what = fmt::format("PPS gpio:{}:{}", chip, line);
  errno = 0;
  chip_ = chip.starts_with('/') ? gpiod_chip_open(chip.c_str()) : gpiod_chip_open_lookup(chip.c_str());
  if (chip_ == nullptr) {
    throw std::runtime_error(fmt::format("{}: {}", what, chip_failure(chip, errno == 0 ? ENOENT : errno)));
  }
  const auto fail = [&](const std::string& why) {
    gpiod_chip_close(chip_);
    chip_ = nullptr;
    return std::runtime_error(fmt::format("{}: {}", what, why));
  };
  const std::string chip_name = gpiod_chip_name(chip_) ? gpiod_chip_name(chip_) : chip;
  unsigned offset = 0;
  const auto [end, ec] = std::from_chars(line.data(), line.data() + line.size(), offset);
  if (ec == std::errc{} && end == line.data() + line.size()) {
    const unsigned count = gpiod_chip_num_lines(chip_);
    if (offset >= count) {
      throw fail(fmt::format("{} has {} lines (0..{}); there is no line {}", chip_name, count,
                             count == 0 ? 0 : count - 1, offset));
    }
    line_ = gpiod_chip_get_line(chip_, offset);
  } else {
    errno = 0;
    line_ = gpiod_chip_find_line(chip_, line.c_str());
    if (line_ == nullptr && (errno == ENOENT || errno == 0)) {
      throw fail(fmt::format("{} has no line named '{}' (`gpioinfo {}` lists them)", chip_name, line, chip_name));
    }
  }
  if (line_ == nullptr) throw fail(fmt::format("cannot get line {} of {}: {}", line, chip_name, posix::errno_text(errno)));
  if (gpiod_line_request_output(line_, kConsumer, idle_level() ? 1 : 0) != 0) {
    const int err = errno;
    const char* consumer = gpiod_line_consumer(line_);
    if (err == EBUSY) {
      throw fail(fmt::format("line {} of {} is in use{}", line, chip_name,
                             consumer ? fmt::format(" by '{}'", consumer) : std::string(" by another program")));
    }
    if (err == EACCES || err == EPERM) {
      throw fail(fmt::format("permission denied requesting line {} of {}", line, chip_name));
    }
    throw fail(fmt::format("cannot request line {} of {} as an output: {}", line, chip_name, posix::errno_text(err)));
  }
  description_ = fmt::format("gpio {} line {}", chip_name, line);
  spdlog::info("PPS on {} ({})", description_, polarity == PpsPolarity::active_high ? "active high" : "active low");
}

GpioPps::~GpioPps() {
  if (line_ != nullptr) {
    (void)gpiod_line_set_value(line_, idle_level() ? 1 : 0);
    gpiod_line_release(line_);
  }
  if (chip_ != nullptr) gpiod_chip_close(chip_);
}

bool GpioPps::drive(bool level, std::string& error_text) {
  if (gpiod_line_set_value(line_, level ? 1 : 0) != 0) {
    error_text = fmt::format("gpiod_line_set_value: {}", posix::errno_text(errno));
    return false;
  }
  return true;
}

}  // namespace gpsemu::transport
