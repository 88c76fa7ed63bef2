// FileOutput: the bytes in the file (or on standard output) are exactly the epochs written,
// buffered for batch generation or handed over at once in real time.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "transport/file_output.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu::transport {
namespace {
namespace file_test {

namespace fs = std::filesystem;

using test::read_file;

std::string epoch(int k) {
  return "$GPGGA,1200" + std::to_string(10 + k % 50) +
         ".00,4717.11399,N,00833.91590,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n";
}

class FileOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string templ = (test::scratch_root() / "gpsemu_file_XXXXXX").string();
    ASSERT_NE(::mkdtemp(templ.data()), nullptr);
    dir_ = templ;
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(FileOutputTest, FileHoldsExactlyTheEpochsWritten) {
  const fs::path path = dir_ / "out.nmea";
  std::string expected;
  {
    FileOutput out(path, false);
    EXPECT_EQ(out.describe(), "file " + path.string());
    // More than the buffer holds, so some blocks go out before the final flush.
    for (int k = 0; expected.size() < 3 * FileOutput::kBufferBytes; ++k) {
      ASSERT_EQ(out.write_epoch(epoch(k)), WriteStatus::ok);
      expected += epoch(k);
    }
    out.flush();
    EXPECT_EQ(read_file(path), expected);
    EXPECT_EQ(out.stats().bytes_written, expected.size());
  }
  EXPECT_EQ(read_file(path), expected);
}

TEST_F(FileOutputTest, BatchModeBuffersUntilFlush) {
  const fs::path path = dir_ / "out.nmea";
  FileOutput out(path, false);
  ASSERT_EQ(out.write_epoch(epoch(0)), WriteStatus::ok);
  EXPECT_EQ(read_file(path), "");
  out.flush();
  EXPECT_EQ(read_file(path), epoch(0));
}

TEST_F(FileOutputTest, RealTimeModeHandsOverEachEpoch) {
  const fs::path path = dir_ / "out.nmea";
  FileOutput out(path, true);
  std::string expected;
  for (int k = 0; k < 5; ++k) {
    ASSERT_EQ(out.write_epoch(epoch(k)), WriteStatus::ok);
    expected += epoch(k);
    EXPECT_EQ(read_file(path), expected);  // what `tail -f` would see
  }
}

TEST_F(FileOutputTest, ExistingFileIsTruncated) {
  const fs::path path = dir_ / "out.nmea";
  std::ofstream(path) << "old contents that are longer than one epoch ........................"
                         "......................................................";
  {
    FileOutput out(path, false);
    ASSERT_EQ(out.write_epoch(epoch(1)), WriteStatus::ok);
  }
  EXPECT_EQ(read_file(path), epoch(1));
}

TEST_F(FileOutputTest, NothingChangesBeforeCommitOrTheFirstWrite) {
  const fs::path existing = dir_ / "existing.nmea";
  const fs::path missing = dir_ / "missing.nmea";
  std::ofstream(existing) << "kept\n";
  {
    FileOutput kept(existing, false);
    FileOutput created(missing, false);
    EXPECT_TRUE(fs::exists(missing));  // opened (so start-up fails early), not yet taken over
  }  // start-up failed: dropped before commit()
  EXPECT_EQ(read_file(existing), "kept\n");
  EXPECT_FALSE(fs::exists(missing));
  {
    FileOutput out(existing, false);
    out.commit();
    EXPECT_EQ(read_file(existing), "");
  }
  EXPECT_TRUE(fs::exists(existing));
}

TEST_F(FileOutputTest, AppendKeepsWhatTheFileHeld) {
  const fs::path path = dir_ / "log.nmea";
  std::ofstream(path) << "before\n";
  {
    FileOutput out(path, true, FileMode::append);
    out.commit();
    ASSERT_EQ(out.write_epoch(epoch(1)), WriteStatus::ok);
  }
  EXPECT_EQ(read_file(path), "before\n" + epoch(1));
}

TEST_F(FileOutputTest, NewRefusesAnExistingFileOrSymlinkAndCreatesAMissingOne) {
  const fs::path path = dir_ / "out.nmea";
  std::ofstream(path) << "precious\n";
  fs::create_symlink(dir_ / "nowhere", dir_ / "dangling");
  for (const fs::path& p : {path, dir_ / "dangling"}) {
    try {
      FileOutput out(p, false, FileMode::create_new);
      ADD_FAILURE() << "mode new accepted the existing " << p;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(p.string() + " already exists"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(read_file(path), "precious\n");
  EXPECT_FALSE(fs::exists(dir_ / "nowhere"));
  {
    FileOutput out(dir_ / "fresh.nmea", false, FileMode::create_new);
    out.commit();
    ASSERT_EQ(out.write_epoch(epoch(2)), WriteStatus::ok);
  }
  EXPECT_EQ(read_file(dir_ / "fresh.nmea"), epoch(2));
}

TEST_F(FileOutputTest, UnopenablePathThrowsNamingPath) {
  for (const fs::path& path : {dir_ / "no-such-dir" / "out.nmea", dir_}) {
    try {
      FileOutput out(path, false);
      ADD_FAILURE() << "no exception for " << path;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
  }
}

TEST_F(FileOutputTest, StdoutWritesToFileDescriptorOne) {
  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::dup2(pipe_fds[1], STDOUT_FILENO);
    ::close(pipe_fds[0]);
    ::close(pipe_fds[1]);
    bool ok = true;
    {
      const auto out = FileOutput::to_stdout(false);
      ok = out->describe() == "stdout";
      for (int k = 0; k < 3; ++k) ok = ok && out->write_epoch(epoch(k)) == WriteStatus::ok;
    }  // destruction flushes and leaves fd 1 open
    ok = ok && ::write(STDOUT_FILENO, "END", 3) == 3;
    ::_exit(ok ? 0 : 1);
  }
  ::close(pipe_fds[1]);
  std::string got;
  for (;;) {
    pollfd pfd{pipe_fds[0], POLLIN, 0};
    ASSERT_EQ(::poll(&pfd, 1, 5000), 1) << "child wrote nothing for 5 s";
    char buf[4096];
    const ssize_t n = ::read(pipe_fds[0], buf, sizeof buf);
    if (n <= 0) break;
    got.append(buf, static_cast<std::size_t>(n));
  }
  ::close(pipe_fds[0]);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_EQ(got, epoch(0) + epoch(1) + epoch(2) + "END");
}

}  // namespace file_test
}  // namespace
}  // namespace gpsemu::transport
