#include <dirent.h>
#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <mutex>
#include <vector>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/common/parallel.h"
#include "canopy/common/printable.h"
#include "canopy/common/rng.h"
#include "canopy/common/share.h"
#include "canopy/common/units.h"

using namespace canopy::common;

namespace {

std::string make_dir(const std::string& name) {
  // Under common/: other test modules own CANOPY_TEST_TMP/<module>/ (tests/cli uses cli/).
  const std::string d = std::string(CANOPY_TEST_TMP) + "/common/" + name;
  std::string cmd = "rm -rf '" + d + "' && mkdir -p '" + d + "'";
  REQUIRE(std::system(cmd.c_str()) == 0);
  return d;
}

int count_entries(const std::string& dir) {
  int n = 0;
  DIR* d = opendir(dir.c_str());
  while (dirent* e = readdir(d)) {
    std::string s = e->d_name;
    if (s != "." && s != "..") ++n;
  }
  closedir(d);
  return n;
}
}  // namespace

TEST_CASE("lengths parse with units, bare numbers are metres") {
  CHECK(parse_length("128mm") == Approx(0.128));
  CHECK(parse_length("12.8cm") == Approx(0.128));
  CHECK(parse_length("0.128m") == Approx(0.128));
  CHECK(parse_length("0.128") == Approx(0.128));
  CHECK(parse_length("-2m") == Approx(-2.0));
  CHECK(parse_length("1e3mm") == Approx(1.0));
  CHECK_THROWS_AS(parse_length("12 furlongs"), UsageError);
  CHECK_THROWS_AS(parse_length("mm"), UsageError);
  CHECK_THROWS_AS(parse_length(""), UsageError);
  CHECK_THROWS_AS(parse_length("nan"), UsageError);
}

TEST_CASE("angles parse with units, bare numbers are degrees") {
  CHECK(parse_angle("10deg") == Approx(10 * kPi / 180));
  CHECK(parse_angle("10") == Approx(10 * kPi / 180));
  CHECK(parse_angle("0.5rad") == Approx(0.5));
  CHECK_THROWS_AS(parse_angle("10grad"), UsageError);
}

TEST_CASE("formatted quantities parse back to the same value") {
  for (double v : {0.128, 0.008, 2.0, 0.512, 12.2}) CHECK(parse_length(format_length(v)) == v);
  CHECK(format_length(0.128) == "128mm");
  CHECK(format_length(10.0) == "10m");
  CHECK(format_length(0.03) == "30mm");
  CHECK(format_length(12.2) == "12.2m");
  CHECK(parse_angle(format_angle(kPi / 8)) == Approx(kPi / 8).epsilon(1e-15));
}

TEST_CASE("Rng is reproducible and has the right moments") {
  Rng a(7), b(7), c(8);
  bool differs = false;
  for (int i = 0; i < 100; ++i) {
    const auto x = a.next_u64();
    CHECK(x == b.next_u64());
    differs |= x != c.next_u64();
  }
  CHECK(differs);
  Rng r(42);
  const int n = 200000;
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = r.normal();
    s += x;
    s2 += x * x;
  }
  const double mean = s / n, var = s2 / n - mean * mean;
  CHECK(std::fabs(mean) < 5.0 / std::sqrt(n));
  CHECK(var == Approx(1.0).margin(0.02));
  double u = 0;
  for (int i = 0; i < n; ++i) u += r.uniform();
  CHECK(u / n == Approx(0.5).margin(0.005));
  for (int i = 0; i < 1000; ++i) CHECK(r.below(7) < 7);
}

TEST_CASE("derived seeds are stable and key-dependent") {
  CHECK(derive_seed(1, "sedan/circle") == derive_seed(1, "sedan/circle"));
  CHECK(derive_seed(1, "sedan/circle") != derive_seed(1, "sedan/flyby"));
  CHECK(derive_seed(1, "x") != derive_seed(2, "x"));
}

TEST_CASE("atomic output appears only on commit and leaves no temporary file") {
  const std::string dir = make_dir("atomic");
  const std::string path = dir + "/out.pcd";
  {
    AtomicOutput out(path);
    out.stream() << "partial";
    CHECK(count_entries(dir) == 1);  // only the temporary file
    struct stat st {};
    CHECK(stat(path.c_str(), &st) != 0);
  }  // destroyed without commit: as if the tool failed
  CHECK(count_entries(dir) == 0);
  write_file_atomic(path, "complete");
  CHECK(read_file(path) == "complete");
  CHECK(count_entries(dir) == 1);
  // A failure midway keeps the previous complete file.
  try {
    AtomicOutput out(path);
    out.stream() << "half";
    throw Error("boom");
  } catch (const Error&) {}
  CHECK(read_file(path) == "complete");
  CHECK(count_entries(dir) == 1);
}

TEST_CASE(
    "same_file_contents: one file, or two files with the same bytes; never a missing file or a directory") {
  const std::string dir = make_dir("samebytes");
  write_file_atomic(dir + "/a", "points");
  write_file_atomic(dir + "/b", "points");
  write_file_atomic(dir + "/c", "pointz");
  write_file_atomic(dir + "/d", "points, longer");
  CHECK(same_file_contents(dir + "/a", dir + "/a"));
  CHECK(same_file_contents(dir + "/a", dir + "/b"));
  CHECK_FALSE(same_file_contents(dir + "/a", dir + "/c"));  // same size, other bytes
  CHECK_FALSE(same_file_contents(dir + "/a", dir + "/d"));
  CHECK_FALSE(same_file_contents(dir + "/a", dir + "/missing"));
  CHECK_FALSE(same_file_contents(dir, dir + "/a"));
}

TEST_CASE("reading a missing file or a directory is a DataError naming it") {
  const std::string dir = make_dir("readerr");
  try {
    read_file(dir);
    FAIL("no error");
  } catch (const DataError& e) {
    CHECK(std::string(e.what()).find(dir) != std::string::npos);
    CHECK(std::string(e.what()).find("directory") != std::string::npos);
    CHECK(e.exit_code() == 1);
  }
  CHECK_THROWS_AS(read_file(dir + "/missing.pcd"), DataError);
  CHECK_THROWS_AS(AtomicOutput(dir), DataError);
}

TEST_CASE("control bytes in messages: printable escapes all, a DataError keeps newline and tab") {
  using canopy::common::printable;
  const std::string raw = std::string("a\0b\x1b[31m\tc\nd\x7f", 13);
  CHECK(printable(raw) == "a\\x00b\\x1b[31m\\x09c\\x0ad\\x7f");
  const DataError e("m.txt", "line 1: unknown record '" + raw + "'");
  // The whole text survives the NUL (what() was cut there before stop 68).
  CHECK(std::string(e.what()) == "m.txt: line 1: unknown record 'a\\x00b\\x1b[31m\tc\nd\\x7f'");
  CHECK(e.cause() == "line 1: unknown record '" + raw + "'");
}

// ---- outputs that are not plain files (issue 12) --------------------------------------------

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

mode_t lmode(const std::string& path) {
  struct stat st {};
  REQUIRE(lstat(path.c_str(), &st) == 0);
  return st.st_mode;
}

// A private character device like the machine's (1,3 = null, 1,7 = full); false when this
// process may not create devices (not root, or a container without CAP_MKNOD).
bool make_char_device(const std::string& path, unsigned major, unsigned minor) {
  return mknod(path.c_str(), S_IFCHR | 0666, makedev(major, minor)) == 0;
}

}  // namespace

TEST_CASE("an existing FIFO output is written through, not replaced") {
  const std::string dir = make_dir("fifo");
  const std::string fifo = dir + "/out.pcd";
  REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
  // The reader opens first (non-blocking, so no thread is needed and a writer that never
  // comes cannot hang the test); the data fits the pipe buffer.
  const int rd = open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  REQUIRE(rd >= 0);
  const std::string data(5000, 'x');
  write_file_atomic(fifo, data);
  std::string got;
  char buf[8192];
  for (ssize_t n; (n = read(rd, buf, sizeof buf)) > 0;) got.append(buf, static_cast<std::size_t>(n));
  close(rd);
  CHECK(got == data);
  CHECK(S_ISFIFO(lmode(fifo)));
  CHECK(writes_through(fifo));
  CHECK(writes_through("-"));
  CHECK_FALSE(writes_through(dir + "/absent.pcd"));
  CHECK(count_entries(dir) == 1);  // no temporary file beside it
}

TEST_CASE("a symbolic link output replaces the file it points to; the link stays") {
  const std::string dir = make_dir("symlink");
  REQUIRE(std::system(("mkdir -p '" + dir + "/target'").c_str()) == 0);
  const std::string target = dir + "/target/real.pcd", link = dir + "/link.pcd";
  write_file_atomic(target, "old");
  REQUIRE(chmod(target.c_str(), 0640) == 0);
  REQUIRE(symlink("target/real.pcd", link.c_str()) == 0);  // relative to the link's directory
  write_file_atomic(link, "new");
  CHECK(S_ISLNK(lmode(link)));
  CHECK(slurp(target) == "new");
  CHECK((lmode(target) & 07777) == 0640);  // the replaced file keeps its permission bits
  CHECK(count_entries(dir) == 2);          // link.pcd, target/
  CHECK(count_entries(dir + "/target") == 1);

  // A chain of links, and a dangling link: the file it names is created (as `>` would).
  const std::string chain = dir + "/chain.pcd";
  REQUIRE(symlink("link.pcd", chain.c_str()) == 0);
  write_file_atomic(chain, "via chain");
  CHECK(slurp(target) == "via chain");
  CHECK(S_ISLNK(lmode(chain)));
  const std::string dangling = dir + "/dangling.pcd";
  REQUIRE(symlink("target/created.pcd", dangling.c_str()) == 0);
  write_file_atomic(dangling, "created");
  CHECK(S_ISLNK(lmode(dangling)));
  CHECK(slurp(dir + "/target/created.pcd") == "created");
  // A loop is an error naming the path.
  const std::string loop = dir + "/loop.pcd";
  REQUIRE(symlink("loop.pcd", loop.c_str()) == 0);
  CHECK_THROWS_WITH(write_file_atomic(loop, "x"),
                    Catch::Contains("loop.pcd") && Catch::Contains("symbolic links"));
}

TEST_CASE("a character device output is written through and keeps its type") {
  const std::string dir = make_dir("chardev");
  const std::string null = dir + "/null", full = dir + "/full";
  if (!make_char_device(null, 1, 3) || !make_char_device(full, 1, 7)) {
    WARN("cannot create device nodes here (not root): character-device case not run");
    return;
  }
  write_file_atomic(null, "discarded");
  struct stat st {};
  REQUIRE(lstat(null.c_str(), &st) == 0);
  CHECK(S_ISCHR(st.st_mode));
  CHECK(st.st_rdev == makedev(1, 3));
  // Writing to a full device is an error naming it; the device stays.
  CHECK_THROWS_WITH(write_file_atomic(full, std::string(10000, 'x')),
                    Catch::Contains("full") && Catch::Contains("write failed"));
  CHECK(S_ISCHR(lmode(full)));
  CHECK(count_entries(dir) == 2);
}

TEST_CASE("outputs are checked before the work: missing directory, directory, socket") {
  const std::string dir = make_dir("check");
  CHECK_NOTHROW(check_output("-"));
  CHECK_NOTHROW(check_output(dir + "/new.pcd"));
  CHECK_THROWS_WITH(check_output(dir + "/nodir/x.pcd"),
                    Catch::Contains(dir + "/nodir") && Catch::Contains("does not exist"));
  CHECK_THROWS_AS(check_output(dir + "/nodir/x.pcd"), DataError);
  CHECK_THROWS_WITH(check_output(dir), Catch::Contains("is a directory"));
  const std::string sock = dir + "/sock";
  const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", sock.c_str());
  if (sock.size() < sizeof addr.sun_path && bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
    CHECK_THROWS_WITH(check_output(sock), Catch::Contains("socket"));
    CHECK_THROWS_AS(write_file_atomic(sock, "x"), DataError);
    struct stat st {};
    CHECK((lstat(sock.c_str(), &st) == 0 && S_ISSOCK(st.st_mode)));
  }
  close(fd);
}

TEST_CASE("an output set refuses two names of one file") {
  const std::string dir = make_dir("sameset");
  REQUIRE(std::system(("mkdir -p '" + dir + "/sub'").c_str()) == 0);
  {
    OutputSet set;
    set.add(dir + "/x.json", "-o");
    CHECK_THROWS_AS(set.add(dir + "/x.json", "--colored"), UsageError);
    CHECK_THROWS_AS(set.add(dir + "/./x.json", "--colored"), UsageError);
    CHECK_THROWS_AS(set.add(dir + "/sub/../x.json", "--colored"), UsageError);
    CHECK_NOTHROW(set.add(dir + "/y.ply", "--colored"));
  }
  REQUIRE(symlink("x.json", (dir + "/alias.json").c_str()) == 0);  // dangling until written
  {
    OutputSet set;
    set.add(dir + "/x.json", "-o");
    CHECK_THROWS_WITH(set.add(dir + "/alias.json", "--colored"), Catch::Contains("same file"));
  }
  write_file_atomic(dir + "/x.json", "{}");
  {
    OutputSet set;
    set.add(dir + "/alias.json", "-o");
    CHECK_THROWS_AS(set.add(dir + "/x.json", "--colored"), UsageError);
    set.add("-", "--colored");
    CHECK_THROWS_WITH(set.add("-", "--other"), Catch::Contains("stdout"));
  }
}

TEST_CASE("an output set writes every output or none") {
  const std::string dir = make_dir("outset");
  {
    OutputSet set;
    set.add(dir + "/a.csv", "--results");
    set.add(dir + "/b.md", "--results");
    set.set(dir + "/a.csv", "a");
    set.set(dir + "/b.md", "b");
    set.commit();
  }
  CHECK(slurp(dir + "/a.csv") == "a");
  CHECK(slurp(dir + "/b.md") == "b");
  // The second output cannot be written at commit (its path became a directory after the
  // check): neither is replaced and no temporary file is left.
  {
    OutputSet set;
    set.add(dir + "/a.csv", "--results");
    set.add(dir + "/c.md", "--results");
    REQUIRE(std::system(("mkdir '" + dir + "/c.md'").c_str()) == 0);
    set.set(dir + "/a.csv", "A");
    set.set(dir + "/c.md", "C");
    CHECK_THROWS_AS(set.commit(), DataError);
  }
  CHECK(slurp(dir + "/a.csv") == "a");
  CHECK(count_entries(dir) == 3);  // a.csv, b.md, c.md/
  // A failing write-through target (a full device) after a complete temporary file: the
  // regular output is not moved into place either.
  const std::string full = dir + "/full";
  if (make_char_device(full, 1, 7)) {
    OutputSet set;
    set.add(dir + "/a.csv", "--colored");
    set.add(full, "-o");
    set.set(dir + "/a.csv", "AAA");
    set.set(full, std::string(10000, 'x'));
    CHECK_THROWS_AS(set.commit(), DataError);
    CHECK(slurp(dir + "/a.csv") == "a");
    CHECK(S_ISCHR(lmode(full)));
    CHECK(count_entries(dir) == 4);
  }
}

namespace {
extern "C" void exit_three(int) { _exit(3); }
}  // namespace

TEST_CASE("a signal removes pending temporary files, also when the program has its own handler") {
  const std::string dir = make_dir("signal");
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    AtomicOutput first(dir + "/first.pcd");
    // The program installs its own SIGTERM handler after the first output was created (as a
    // tool that stops its children would); outputs created later still clean up, then call it.
    struct sigaction sa {};
    sa.sa_handler = exit_three;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, nullptr);
    AtomicOutput second(dir + "/second.pcd");
    if (count_entries(dir) != 2) _exit(10);
    raise(SIGTERM);
    _exit(11);
  }
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 3);  // the program's handler ran
  CHECK(count_entries(dir) == 0);   // after both temporary files were removed
}

TEST_CASE("an ignored signal stays ignored (nohup)") {
  const std::string dir = make_dir("nohup");
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    signal(SIGHUP, SIG_IGN);
    AtomicOutput out(dir + "/out.pcd");
    raise(SIGHUP);
    out.stream() << "done";
    out.commit();
    _exit(0);
  }
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  CHECK((WIFEXITED(status) && WEXITSTATUS(status) == 0));
  CHECK(slurp(dir + "/out.pcd") == "done");
}

TEST_CASE("numbers on the command line are decimal only") {
  CHECK(decimal_prefix("128mm") == 3);
  CHECK(decimal_prefix("-1.5e-3m") == 7);
  CHECK(decimal_prefix(".5") == 2);
  CHECK(decimal_prefix("5.") == 2);
  CHECK(decimal_prefix("0x10") == 1);
  CHECK(decimal_prefix("inf") == 0);
  CHECK(decimal_prefix(" 1") == 0);
  CHECK(decimal_prefix("1e") == 1);
  CHECK_THROWS_AS(parse_length("0x10mm"), UsageError);
  CHECK_THROWS_AS(parse_length("0x1p3"), UsageError);
  CHECK_THROWS_AS(parse_length("infinity"), UsageError);
  CHECK_THROWS_AS(parse_length(" 1m"), UsageError);
  CHECK_THROWS_AS(parse_angle("0x10"), UsageError);
  CHECK_THROWS_AS(parse_length("1e999"), UsageError);
  using canopy::common::detail::check_integer;
  using canopy::common::detail::check_real;
  const unsigned long long u64 = ~0ULL;
  CHECK(check_integer("7", false, 0, u64).empty());
  CHECK(check_integer("18446744073709551615", false, 0, u64).empty());
  CHECK_FALSE(check_integer("18446744073709551616", false, 0, u64).empty());
  CHECK_FALSE(check_integer("-1", false, 0, u64).empty());
  CHECK_FALSE(check_integer("0x10", false, 0, u64).empty());
  CHECK_FALSE(check_integer("1e3", true, -5, 5).empty());
  CHECK_FALSE(check_integer("6", true, -5, 5).empty());
  CHECK(check_integer("-5", true, -5, 5).empty());
  CHECK(check_real("1e-10").empty());
  CHECK(check_real("0.8333333333333334").empty());
  CHECK_FALSE(check_real("nan").empty());
  CHECK_FALSE(check_real("0x1p3").empty());
  CHECK_FALSE(check_real("1e400").empty());
}

TEST_CASE("share_dir: CANOPY_SHARE, else beside the executable, else the source tree") {
  const char* saved = std::getenv("CANOPY_SHARE");
  const std::string keep = saved == nullptr ? "" : saved;
  const std::string dir = make_dir("share");
  setenv("CANOPY_SHARE", dir.c_str(), 1);
  CHECK(share_dir() == dir);
  setenv("CANOPY_SHARE", (dir + "/absent").c_str(), 1);
  CHECK_THROWS_WITH(share_dir(), Catch::Contains("CANOPY_SHARE") && Catch::Contains("absent"));
  unsetenv("CANOPY_SHARE");
  // The test binary sits in build/bin, which has no ../share/canopy: the source tree's share/.
  CHECK(share_dir() == std::string(CANOPY_SOURCE_DIR) + "/share");
  if (saved != nullptr) setenv("CANOPY_SHARE", keep.c_str(), 1);
}

namespace {

// Runs a Tool with the given arguments; returns the exit code, stderr in *err.
int run_tool(std::vector<std::string> args, std::string* err, bool* ran = nullptr) {
  Tool tool("demo", "a demo tool", true);
  std::string in = "-", out = "-";
  double voxel = 0.128;
  int count = 3;
  tool.add_input(&in);
  tool.add_output(&out);
  tool.add_length("--voxel", &voxel, "voxel edge", 1.0);
  tool.add("--min-points", &count, "a count");
  args.insert(args.begin(), "demo");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(&a[0]);
  // stderr captured at the descriptor: errors go through std::cerr, warnings through stdio.
  const std::string file = std::string(CANOPY_TEST_TMP) + "/common/run_tool.err";
  std::fflush(stderr);
  const int saved = dup(STDERR_FILENO);
  const int fd = open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  dup2(fd, STDERR_FILENO);
  close(fd);
  bool body = false;
  const int rc = tool.run(static_cast<int>(argv.size()), argv.data(), [&] { body = true; });
  std::cerr.flush();
  std::fflush(stderr);
  dup2(saved, STDERR_FILENO);
  close(saved);
  *err = slurp(file);
  if (ran != nullptr) *ran = body;
  return rc;
}

}  // namespace

TEST_CASE("a stray word gets 'use -i', a mistyped option 'did you mean'") {
  const std::string dir = make_dir("cli");
  std::string err;
  CHECK(run_tool({"scan.pcd"}, &err) == 2);
  CHECK_THAT(err, Catch::Contains("unexpected argument 'scan.pcd': use -i scan.pcd"));
  CHECK(run_tool({"-i", "a.pcd", "b.pcd"}, &err) == 2);
  CHECK_THAT(err, Catch::Contains("'b.pcd'") && Catch::Contains("one input"));
  CHECK(run_tool({"--vxoel", "8mm", "-i", "a.pcd"}, &err) == 2);
  CHECK_THAT(err, Catch::Contains("unknown option '--vxoel': did you mean --voxel?"));
  CHECK(run_tool({"--min-point=3", "-i", "a.pcd"}, &err) == 2);
  CHECK_THAT(err, Catch::Contains("did you mean --min-points?"));
  CHECK(run_tool({"--vox", "8mm", "-i", "a.pcd"}, &err) == 2);
  CHECK_THAT(err, Catch::Contains("did you mean --voxel?"));
  CHECK(run_tool({"--zzzzzz", "-i", "a.pcd"}, &err) == 2);
  CHECK_THAT(err, Catch::Contains("unknown option '--zzzzzz'") && !Catch::Contains("did you mean"));
  // Strict numbers: no hex, no sign wrap-around, no overflow.
  CHECK(run_tool({"--seed", "-1", "-i", "a.pcd"}, &err) == 2);
  CHECK_THAT(err, Catch::Contains("--seed"));
  CHECK(run_tool({"--seed", "0x10", "-i", "a.pcd"}, &err) == 2);
  CHECK(run_tool({"--min-points", "0x10", "-i", "a.pcd"}, &err) == 2);
  CHECK(run_tool({"--min-points", "99999999999", "-i", "a.pcd"}, &err) == 2);
  CHECK(run_tool({"--voxel", "0x10mm", "-i", "a.pcd"}, &err) == 2);
  CHECK(run_tool({"--threads", "010x", "-i", "a.pcd"}, &err) == 2);
  bool ran = false;
  CHECK(run_tool({"--seed", "18446744073709551615", "-i", "a.pcd", "-o", dir + "/x"}, &err, &ran) == 0);
  CHECK(ran);
}

TEST_CASE("bare lengths over the warning bound draw a warning, not an error") {
  const std::string dir = make_dir("cli_warn");
  std::string err;
  CHECK(run_tool({"--voxel", "8", "-i", "a.pcd", "-o", dir + "/x"}, &err) == 0);
  CHECK_THAT(err, Catch::Contains("warning") && Catch::Contains("bare numbers are metres") &&
                      Catch::Contains("did you mean 8mm?"));
  CHECK(run_tool({"--voxel", "2m", "-i", "a.pcd", "-o", dir + "/x"}, &err) == 0);
  CHECK_THAT(err, Catch::Contains("warning") && Catch::Contains("over 1m"));
  CHECK(run_tool({"--voxel", "0.5", "-i", "a.pcd", "-o", dir + "/x"}, &err) == 0);
  CHECK(err.empty());
}

TEST_CASE("Tool::run checks the outputs before the body runs") {
  const std::string dir = make_dir("cli_out");
  std::string err;
  bool ran = true;
  CHECK(run_tool({"-i", "a.pcd", "-o", dir + "/nodir/x.pcd"}, &err, &ran) == 1);
  CHECK_FALSE(ran);
  CHECK_THAT(err, Catch::Contains(dir + "/nodir") && Catch::Contains("does not exist"));
}

TEST_CASE("mix64 is the splitmix64 finaliser; Rng and derive_seed are unchanged by sharing it") {
  // splitmix64 seeded with 0: first outputs 0xE220A8397B1DCDAF, 0x6E789E6AA1B965F4.
  CHECK(mix64(0) == 0xE220A8397B1DCDAFULL);
  CHECK(mix64(0x9E3779B97F4A7C15ULL) == 0x6E789E6AA1B965F4ULL);
  // Values of the code before mix64 moved into common (common/src/rng.cpp at 2c12d5e, built
  // separately): seeds and streams are unchanged.
  CHECK(derive_seed(0, "sedan/circle/noise-8") == 17044524121595778235ULL);
  Rng a(42);
  CHECK(a.next_u64() == 1546998764402558742ULL);
}

TEST_CASE("parallel_for covers [0, n) once in fixed chunks and rethrows a worker's error") {
  for (int threads : {1, 2, 3, 8}) {
    for (std::size_t n : {0u, 1u, 5u, 100u}) {
      std::vector<int> hits(n, 0);
      std::vector<std::pair<std::size_t, std::size_t>> chunks;
      std::mutex m;
      parallel_for(n, threads, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) ++hits[i];
        std::lock_guard<std::mutex> lock(m);
        chunks.emplace_back(b, e);
      });
      INFO("threads " << threads << ", n " << n);
      CHECK(std::all_of(hits.begin(), hits.end(), [](int h) { return h == 1; }));
      const std::size_t t = std::min<std::size_t>(threads, n);
      CHECK(chunks.size() == (t <= 1 ? 1 : (n + (n + t - 1) / t - 1) / ((n + t - 1) / t)));
    }
  }
  CHECK_THROWS_WITH(parallel_for(10, 4,
                                 [](std::size_t b, std::size_t) {
                                   if (b > 0) throw Error("chunk at " + std::to_string(b));
                                 }),
                    "chunk at 3");
}

// --- issue 25 (round 3): numbers and outputs ---------------------------------------------

TEST_CASE("round 3: '8 mm', 1e-400, -0 and hex are refused on the command line") {
  // A space between number and unit (a shell word or config value of two words).
  CHECK_THROWS_WITH(parse_length("8 mm"), Catch::Contains("no space between the number and its unit") &&
                                              Catch::Contains("write 8mm"));
  CHECK_THROWS_AS(parse_angle("10 deg"), UsageError);
  // Underflow: 1e-400 read as 0, 1e-310 as a subnormal.
  CHECK_THROWS_WITH(parse_length("1e-400"), Catch::Contains("out of range"));
  CHECK_THROWS_WITH(parse_length("1e-310mm"), Catch::Contains("out of range"));
  CHECK(parse_length("1e-300") == 1e-300);
  CHECK(parse_length("0e-400") == 0.0);  // a zero mantissa is zero, whatever the exponent
  // Negative zero.
  CHECK_THROWS_WITH(parse_length("-0"), Catch::Contains("negative zero"));
  CHECK_THROWS_WITH(parse_angle("-0.0deg"), Catch::Contains("negative zero"));
  CHECK_THROWS_AS(parse_length("-0e5mm"), UsageError);
  CHECK_FALSE(std::signbit(parse_length("0")));
  CHECK(parse_length("-0.5mm") == -0.0005);
  using canopy::common::detail::check_real;
  CHECK_FALSE(check_real("1e-400").empty());
  CHECK_FALSE(check_real("-0").empty());
  CHECK_FALSE(check_real("-0.000").empty());
  CHECK_FALSE(check_real("0x1p0").empty());
  CHECK(check_real("-0.001").empty());
  CHECK(check_real("0").empty());
  // parse_decimal: for options a tool reads itself (fitvox --support, lists).
  CHECK(parse_decimal("0.75", "--support") == 0.75);
  CHECK_THROWS_WITH(parse_decimal("0x1p0", "--support"),
                    Catch::Contains("--support") && Catch::Contains("not a decimal number"));
  CHECK_THROWS_AS(parse_decimal("0x10", "--x"), UsageError);
  CHECK_THROWS_AS(parse_decimal("1e-400", "--x"), UsageError);
  CHECK_THROWS_AS(parse_decimal("-0", "--x"), UsageError);
  CHECK_THROWS_AS(parse_decimal("inf", "--x"), UsageError);
  CHECK_THROWS_AS(parse_decimal("1 ", "--x"), UsageError);
  CHECK_THROWS_AS(parse_decimal("", "--x"), UsageError);
}

TEST_CASE("round 3: a length option's error names the option") {
  std::string err;
  CHECK(run_tool({"--voxel", "8 mm", "-i", "a.pcd"}, &err) == 2);
  CHECK_THAT(err, Catch::Contains("--voxel: '8 mm': no space"));
  CHECK(run_tool({"--voxel", "-0", "-i", "a.pcd"}, &err) == 2);
  CHECK_THAT(err, Catch::Contains("--voxel: '-0' is a negative zero"));
  CHECK(run_tool({"--voxel", "1e-400", "-i", "a.pcd"}, &err) == 2);
  CHECK_THAT(err, Catch::Contains("--voxel: '1e-400' is out of range"));
  CHECK(run_tool({"--min-points", "0x10", "-i", "a.pcd"}, &err) == 2);
  CHECK_THAT(err, Catch::Contains("--min-points"));
}

namespace {

// A pipe whose write end is descriptor `at` (and whose read end is returned in *rd).
void pipe_at(int at, int* rd) {
  int p[2];
  REQUIRE(pipe(p) == 0);
  REQUIRE(dup2(p[1], at) == at);
  close(p[1]);
  *rd = p[0];
}

std::string read_all(int fd) {
  std::string s;
  char buf[256];
  ssize_t n;
  while ((n = read(fd, buf, sizeof buf)) > 0) s.append(buf, static_cast<std::size_t>(n));
  return s;
}

}  // namespace

TEST_CASE("round 3: /dev/fd/N and /proc/self/fd/N name the process's own descriptor, written as is") {
  const int at = 57;
  for (const std::string name : {"/dev/fd/57", "/proc/self/fd/57"}) {
    int rd = -1;
    pipe_at(at, &rd);
    CHECK(writes_through(name));
    CHECK_NOTHROW(check_output(name));
    write_file_atomic(name, "through the pipe");
    close(at);  // the only write end left: the reader sees the end
    CHECK(read_all(rd) == "through the pipe");
    close(rd);
  }
  // Also reached through a link of the user's (`latest -> /dev/fd/57`).
  const std::string dir = make_dir("ownfd");
  REQUIRE(symlink("/proc/self/fd/57", (dir + "/latest").c_str()) == 0);
  int rd = -1;
  pipe_at(at, &rd);
  write_file_atomic(dir + "/latest", "via a link");
  close(at);
  CHECK(read_all(rd) == "via a link");
  close(rd);
  struct stat st {};
  CHECK((lstat((dir + "/latest").c_str(), &st) == 0 && S_ISLNK(st.st_mode)));  // the link stays
  // A file opened for appending is appended to, never truncated or replaced.
  const std::string log = dir + "/log.txt";
  { std::ofstream(log) << "first line\n"; }
  const int fd = open(log.c_str(), O_WRONLY | O_APPEND);
  REQUIRE(dup2(fd, at) == at);
  close(fd);
  struct stat before {};
  REQUIRE(stat(log.c_str(), &before) == 0);
  write_file_atomic("/dev/fd/57", "appended\n");
  write_file_atomic("/proc/self/fd/57", "twice\n");
  close(at);
  CHECK(slurp(log) == "first line\nappended\ntwice\n");
  struct stat after {};
  REQUIRE(stat(log.c_str(), &after) == 0);
  CHECK(after.st_ino == before.st_ino);  // the same file, not a renamed copy
  CHECK(count_entries(dir) == 2);        // no temporary file left beside it
}

TEST_CASE("round 3: a descriptor that is closed or read-only is refused, naming the path") {
  close(58);
  CHECK_THROWS_WITH(check_output("/dev/fd/58"), Catch::Contains("/dev/fd/58") && Catch::Contains("not open"));
  CHECK_THROWS_AS(write_file_atomic("/proc/self/fd/58", "x"), DataError);
  const std::string dir = make_dir("ownfd_ro");
  { std::ofstream(dir + "/in.txt") << "input"; }
  const int fd = open((dir + "/in.txt").c_str(), O_RDONLY);
  REQUIRE(dup2(fd, 58) == 58);
  close(fd);
  CHECK_THROWS_WITH(check_output("/dev/fd/58"), Catch::Contains("reading only"));
  CHECK_THROWS_AS(write_file_atomic("/dev/fd/58", "x"), DataError);
  close(58);
  CHECK(slurp(dir + "/in.txt") == "input");
}

TEST_CASE("round 3: /dev/stdout is stdout: appended with >>, a pipe written, one output with '-'") {
  const std::string dir = make_dir("stdout");
  const std::string log = dir + "/log.txt";
  { std::ofstream(log) << "first line, must survive\n"; }
  // In a child: stdout opened O_APPEND on the log (`tool -o /dev/stdout >> log.txt`).
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_APPEND);
    if (fd < 0 || dup2(fd, STDOUT_FILENO) != STDOUT_FILENO) _exit(3);
    try {
      write_file_atomic("/dev/stdout", "one\n");
      write_file_atomic("/proc/self/fd/1", "two\n");
    } catch (...) { _exit(4); }
    _exit(0);
  }
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  CHECK((WIFEXITED(status) && WEXITSTATUS(status) == 0));
  CHECK(slurp(log) == "first line, must survive\none\ntwo\n");
  // "-" and /dev/stdout are one output: an output set refuses both.
  CHECK(output_identity("-") == output_identity("/dev/stdout"));
  OutputSet set;
  set.add("/dev/stdout", "-o");
  CHECK_THROWS_AS(set.add("-", "--colored"), UsageError);
}

TEST_CASE("round 3: naming_input names the input in a stage's errors, once") {
  CHECK(naming_input("a.pcd", [] { return 7; }) == 7);
  CHECK_THROWS_WITH(naming_input("a.pcd", []() -> int { throw Error("voxel index overflow"); }),
                    "a.pcd: voxel index overflow");
  CHECK_THROWS_AS(naming_input("a.pcd", []() -> int { throw std::runtime_error("extent"); }), DataError);
  CHECK_THROWS_WITH(naming_input("-", []() -> int { throw std::runtime_error("extent"); }),
                    "<stdin>: extent");
  CHECK_THROWS_WITH(naming_input("a.pcd", []() -> int { throw DataError("b.pcd", "bad"); }), "b.pcd: bad");
  CHECK_THROWS_AS(naming_input("a.pcd", []() -> int { throw UsageError("--x"); }), UsageError);
  CHECK_THROWS_AS(naming_input("a.pcd", []() -> int { throw std::bad_alloc(); }), std::bad_alloc);
}
