// stagerun's rules (tools/stagerun/stagerun.h) against the answers of the bash they replaced
// (scripts/stage.sh up to stop 48): the .time format, the progress state's step, the kind of a
// stage, the failure's words, the "done" line, the log's tail, the resources file.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "stagerun/stagerun.h"

namespace sr = canopy::stagerun;

TEST_CASE("stagerun: seconds in milliseconds, as the bash ms() read them") {
  std::int64_t ms = -1;
  CHECK(sr::parse_ms("12.3456", &ms));
  CHECK(ms == 12345);
  CHECK(sr::parse_ms("7", &ms));
  CHECK(ms == 7000);
  CHECK(sr::parse_ms(".5", &ms));
  CHECK(ms == 500);
  CHECK(sr::parse_ms("5.", &ms));
  CHECK(ms == 5000);
  CHECK(sr::parse_ms("1733384079.123456789", &ms));
  CHECK(ms == 1733384079123);
  ms = 42;
  for (const char* bad : {"", ".", "1.2.3", "-1", "1e3", "abc", "1 2"}) {
    INFO(bad);
    CHECK_FALSE(sr::parse_ms(bad, &ms));
  }
  CHECK(ms == 42);  // left as it was
}

TEST_CASE("stagerun: fields as bash's read splits a line") {
  CHECK(sr::read_fields("  a  b\tc d  e  ", 3) == std::vector<std::string>{"a", "b", "c d  e"});
  CHECK(sr::read_fields("a", 3) == std::vector<std::string>{"a", "", ""});
  CHECK(sr::read_fields("", 1) == std::vector<std::string>{""});
  CHECK(sr::first_line("one\ntwo\n") == "one");
  CHECK(sr::first_line("one") == "one");
}

TEST_CASE("stagerun: the kind of a stage") {
  CHECK(sr::stage_kind("out/sedan/circle/noise-16/samples.pcd", {"build/bin/fitvox", "-i", "x"}) ==
        "fitvox:samples.pcd");
  CHECK(sr::stage_kind("out/s/t101/cands/c0012/mesh.ply", {"build/bin/cocone"}) == "cocone:cand/mesh.ply");
  // xvfb-run before the tool: the first word under a bin/ directory names it
  CHECK(sr::stage_kind("res/figures/f12.png", {"xvfb-run", "-a", "/x/bin/figures", "plot"}) ==
        "figures:f##.png");
  CHECK(sr::stage_kind("scan2.pcd", {"sleep", "1"}) == "sleep:scan#.pcd");
}

TEST_CASE("stagerun: the .time file in GNU time's format") {
  sr::Usage u;
  u.wall_us = 12345678;  // 12.345678 s: truncated to hundredths, as GNU time prints
  u.user_us = 2009999;
  u.sys_us = 10000;
  u.max_rss_kib = 65004;
  u.wait_status = 0;
  CHECK(sr::time_file_text(u) == "12.34 65004 2.00 0.01\n");
  CHECK(sr::time_exit_status(u.wait_status) == 0);
  u.wait_status = 3 << 8;  // exit 3
  CHECK(sr::time_file_text(u) == "Command exited with non-zero status 3\n12.34 65004 2.00 0.01\n");
  CHECK(sr::time_exit_status(u.wait_status) == 3);
  u.wait_status = SIGKILL;  // killed
  CHECK(sr::time_file_text(u) == "Command terminated by signal 9\n12.34 65004 2.00 0.01\n");
  CHECK(sr::time_exit_status(u.wait_status) == 137);
  u = sr::Usage{};
  CHECK(sr::time_file_text(u) == "0.00 0 0.00 0.00\n");
}

TEST_CASE("stagerun: the progress state's step") {
  const std::int64_t t0_ms = 1700000000000;
  const std::string state = "3 10 4.000 20.000 1700000000.000 rest\n";
  SECTION("the artifact's previous wall time is its share; the rest of the line is dropped") {
    const auto s = sr::progress_step(state, "", "2.50", "fitvox:samples.pcd", t0_ms + 13000);
    REQUIRE(s.valid);
    CHECK(s.state_line == "4 10 6.500 20.000 1700000000.000\n");
    CHECK(s.count == "4/10 ");
    CHECK(s.left == "  ~27 s left");  // 13 s * 13.5 / 6.5 = 27.0
  }
  SECTION("else its kind's estimate, its tool's, every stage's, else 1 s") {
    const std::string est = "fitvox:samples.pcd 7.25\nfitvox 3\n* 2\n";
    CHECK(sr::progress_step(state, est, "", "fitvox:samples.pcd", t0_ms).state_line ==
          "4 10 11.250 20.000 1700000000.000\n");
    CHECK(sr::progress_step(state, est, "", "fitvox:cand/samples.pcd", t0_ms).state_line ==
          "4 10 7.000 20.000 1700000000.000\n");
    CHECK(sr::progress_step(state, est, "", "cocone:mesh.ply", t0_ms).state_line ==
          "4 10 6.000 20.000 1700000000.000\n");
    CHECK(sr::progress_step(state, "", "", "cocone:mesh.ply", t0_ms).state_line ==
          "4 10 5.000 20.000 1700000000.000\n");
    // a kind's estimate that is no number: the tool's; a last line without its newline is not read
    CHECK(sr::progress_step(state, "fitvox:samples.pcd x\nfitvox 3\n", "", "fitvox:samples.pcd", t0_ms).state_line ==
          "4 10 7.000 20.000 1700000000.000\n");
    CHECK(sr::progress_step(state, "fitvox:samples.pcd 7.25", "", "fitvox:samples.pcd", t0_ms).state_line ==
          "4 10 5.000 20.000 1700000000.000\n");
    // a previous .time whose first word is no wall time (a status line) is not used
    CHECK(sr::progress_step(state, est, "Command", "fitvox:samples.pcd", t0_ms).state_line ==
          "4 10 11.250 20.000 1700000000.000\n");
  }
  SECTION("N never passes M, D never passes E; no time left at the last stage") {
    const auto s = sr::progress_step("10 10 4.000 4.500 1700000000.5\n", "", "1", "k:x", t0_ms + 60000);
    CHECK(s.state_line == "11 11 5.000 5.000 1700000000.5\n");
    CHECK(s.count == "11/11 ");
    CHECK(s.left.empty());
  }
  SECTION("no time left before 1% of the estimated work is done, nor with a clock before T0") {
    CHECK(sr::progress_step("1 1000 0.000 2000.000 1700000000\n", "", "1", "k:x", t0_ms + 1000).left.empty());
    CHECK(sr::progress_step(state, "", "1", "k:x", t0_ms - 1).left.empty());
  }
  SECTION("no state: nothing to write or show") {
    for (const char* bad : {"", "3 x 4 20 1700000000", "3 10 4.000 20.000", "3 10 a 20 1", "-3 10 4 20 1"}) {
      INFO(bad);
      CHECK_FALSE(sr::progress_step(bad, "", "1", "k:x", t0_ms).valid);
    }
  }
  CHECK(sr::left_text(89499) == "~89 s left");
  CHECK(sr::left_text(89999) == "~90 s left");
  CHECK(sr::left_text(90000) == "~2 min left");
  CHECK(sr::left_text(5399999) == "~90 min left");
  CHECK(sr::left_text(5400000) == "~1 h 30 min left");
  CHECK(sr::left_text(7170000) == "~1 h 60 min left");  // (as the bash rounded)
}

TEST_CASE("stagerun: the words of a failure") {
  bool tool = false;
  CHECK(sr::failure_words("Command exited with non-zero status 1", 1, &tool) == "exit 1");
  CHECK(tool);
  CHECK(sr::failure_words("Command exited with non-zero status 125", 125, &tool) == "exit 125");
  CHECK(tool);
  CHECK(sr::failure_words("Command exited with non-zero status 127", 127, &tool) ==
        "exit 127, the command could not run");
  CHECK_FALSE(tool);
  CHECK(sr::failure_words("Command exited with non-zero status 137", 137, &tool) == "exit 137, a signal");
  CHECK_FALSE(tool);
  CHECK(sr::failure_words("Command terminated by signal 9", 137, &tool) == "terminated by signal 9");
  CHECK_FALSE(tool);
  CHECK(sr::failure_words("", 1, &tool) == "exit 1; the tool did not finish");  // srun got no allocation
  CHECK_FALSE(tool);
}

TEST_CASE("stagerun: the done line as the bash printf wrote it") {
  CHECK(sr::cpu_seconds("12.34 65004 2.05 0.99") == "3.04");
  CHECK(sr::cpu_seconds("12.34 65004 2.5 0.99") == "0.00");
  CHECK(
      sr::done_line("4/10 ", "out/a.pcd", "12.34 65004 2.05 0.99", "  ~27 s left") ==
      "done  4/10 out/a.pcd                                                    12.34 s    3.04 cpu     63 MB"
      "  ~27 s left\n");
  CHECK(sr::done_line("", "a/x", "0.00 988 0.00 0.00", "") ==
        "done  a/x                                                           0.00 s    0.00 cpu      0 MB\n");
}

TEST_CASE("stagerun: the log's last lines") {
  CHECK(sr::indented_tail("1\n2\n3\n4\n5\n6\n7\n", 5) == "      3\n      4\n      5\n      6\n      7\n");
  CHECK(sr::indented_tail("1\n2\n", 5) == "      1\n      2\n");
  CHECK(sr::indented_tail("1\n2\n3\n4\n5\n6\n7", 5) == "      3\n      4\n      5\n      6\n      7\n");
  CHECK(sr::indented_tail("\n\n", 5) == "      \n      \n");
  CHECK(sr::indented_tail("", 5).empty());
}

TEST_CASE("stagerun: a recorded failure's one line") {
  // the last line that is not blank, control bytes shown as '?', cut at the bound
  CHECK(sr::last_log_line("a\nfitvox: error: x.pcd: no voxel passed the tests\n\n  \n") ==
        "fitvox: error: x.pcd: no voxel passed the tests");
  CHECK(sr::last_log_line("only") == "only");
  CHECK(sr::last_log_line("x\r\n") == "x?");
  CHECK(sr::last_log_line("\n\n \t\n").empty());
  CHECK(sr::last_log_line("").empty());
  CHECK(sr::last_log_line("a\x1b[31mred\n") == "a?[31mred");
  CHECK(sr::last_log_line("0123456789", 4) == "0123...");
  CHECK(sr::recorded_line("3/9 ", "out/c/samples.pcd", "exit 1", "out/c/samples.pcd.log",
                          "fitvox: error: c.pcd: no voxel passed the tests\n") ==
        "fail  3/9 out/c/samples.pcd (exit 1; recorded as a failed trial): fitvox: error: c.pcd: no voxel "
        "passed the tests\n");
  CHECK(sr::recorded_line("", "a/f", "exit 2", "a/f.log", "\n") ==
        "fail  a/f (exit 2; recorded as a failed trial): see a/f.log\n");
}

TEST_CASE("stagerun: share/resources.ini") {
  const std::string ini =
      "# comment\r\n[default]\ncpus = 1\nmem = 2G\ntime = 10\n\n[ rangetrace ]\n; a comment\ncpus=2\n"
      "time = 01:00:00 \n[fitvox]\nmem = 4G # more\n";
  auto res = [&](const std::vector<std::string>& command) {
    const sr::Resources r = sr::slurm_resources(ini, "r.ini", command);
    return r.section + " " + r.cpus + " " + r.mem + " " + r.time;
  };
  // the section: the first command word whose base name is a [section]; keys it lacks from [default]
  CHECK(res({"xvfb-run", "-a", "build/bin/fitvox"}) == "fitvox 1 4G 10");
  CHECK(res({"build/bin/rangetrace/", "-i", "x"}) == "rangetrace 2 2G 01:00:00");
  CHECK(res({"build/bin/score"}) == "default 1 2G 10");
  CHECK(res({}) == "default 1 2G 10");
  // The shipped file: every tool's values as before the one reader (docs/decisions/ini.md).
  const std::string shipped =
      canopy::common::read_file(std::string(CANOPY_SOURCE_DIR) + "/share/resources.ini");
  auto shipped_res = [&](const char* tool) {
    const sr::Resources r = sr::slurm_resources(shipped, "resources.ini", {std::string("build/bin/") + tool});
    return r.section + " " + r.cpus + " " + r.mem + " " + r.time;
  };
  CHECK(shipped_res("rangetrace") == "rangetrace 2 2G 00:30:00");
  CHECK(shipped_res("fitvox") == "fitvox 1 2G 00:10:00");
  CHECK(shipped_res("figures") == "figures 1 2G 00:10:00");
  CHECK(shipped_res("ncut") == "default 1 1G 00:10:00");
  // Errors name the file and the line.
  auto error = [](const std::string& text) {
    try {
      sr::slurm_resources(text, "r.ini", {"fitvox"});
    } catch (const canopy::common::DataError& e) { return std::string(e.what()); }
    return std::string();
  };
  CHECK(error("[default]\ncpus = 1\nmem = 1G\n") == "r.ini: no 'time' for [default] or [default]");
  CHECK(error("[default]\ncpus = 1\nmem = 1G\ntime = 1\n[fitvox]\nmem =\n") ==
        "r.ini: line 6: key 'mem' has no value");
  CHECK(error("[default]\ncpus = 1\ncpus = 2\n") ==
        "r.ini: line 3: 'cpus' is given twice, on lines 2 and 3 (a key may appear once)");
  CHECK(error("[default]\ngpus = 1\n") == "r.ini: line 2: unknown key 'gpus' (the keys: cpus, mem, time)");
  CHECK(error("cpus = 1\n[default]\n") == "r.ini: line 1: 'cpus' before any [section]");
  CHECK(error("[default]\ncpus\n") == "r.ini: line 2: expected 'key = value', got 'cpus'");
}

TEST_CASE("stagerun: glibc's huge pages") {
  CHECK(sr::hugepage_tunables(nullptr) == "glibc.malloc.hugetlb=1");
  CHECK(sr::hugepage_tunables("") == "glibc.malloc.hugetlb=1");
  CHECK(sr::hugepage_tunables("glibc.malloc.arena_max=2") ==
        "glibc.malloc.arena_max=2:glibc.malloc.hugetlb=1");
  CHECK(sr::hugepage_tunables("glibc.malloc.hugetlb=0") == "glibc.malloc.hugetlb=0");
  CHECK(sr::hugepage_tunables("a=1:glibc.malloc.hugetlb=2") == "a=1:glibc.malloc.hugetlb=2");
  CHECK(sr::hugepage_tunables("xglibc.malloc.hugetlb=0") == "xglibc.malloc.hugetlb=0:glibc.malloc.hugetlb=1");
}
