// POV-Ray confinement (issue 25, docs/decisions/sandbox.md): the lexical check of user
// includes (layer 2), the bubblewrap jail (layer 1) on its own, the reproducers of round 3
// through the CLI, what happens when bwrap cannot confine, and byte-identical scans with and
// without the jail.
#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/sim/povray_run.h"
#include "canopy/sim/sandbox.h"
#include "support/cli.h"

using namespace canopy;
using namespace canopy::sim;
namespace fs = std::filesystem;

namespace {

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string slurp(const fs::path& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

std::string bin() { return std::string(CANOPY_BIN_DIR) + "/rangetrace"; }
std::string q(const fs::path& p) { return "'" + p.string() + "'"; }
fs::path data(const std::string& name) {
  return fs::path(CANOPY_SOURCE_DIR) / "tests" / "rangetrace" / "data" / "round3" / name;
}

std::string real(const fs::path& p) { return fs::canonical(p).string(); }

// Sets an environment variable for the scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old, had_ = true;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (had_) {
      ::setenv(name_, old_.c_str(), 1);
    } else {
      ::unsetenv(name_);
    }
  }

 private:
  const char* name_;
  std::string old_;
  bool had_ = false;
};

// The message of check_user_include on `text` written as dir/v.inc ("" when accepted).
std::string check_text(const fs::path& dir, const std::string& text, bool unconfined = false) {
  write_text(dir / "v.inc", text);
  try {
    check_user_include(real(dir), "v.inc", unconfined);
  } catch (const common::DataError& e) { return e.what(); }
  return "";
}

// Whether bwrap can confine POV-Ray on this machine (the jail tests are skipped otherwise).
bool bwrap_usable(const fs::path& dir) {
  ScopedEnv mode("CANOPY_POVRAY_SANDBOX", "bwrap");
  try {
    povray_command("povray", {}, real(dir), {}, false);
  } catch (const common::Error& e) {
    WARN("bwrap cannot confine POV-Ray here, jail cases skipped: " << e.what());
    return false;
  }
  return true;
}

// POV-Ray wraps its messages at 80 columns (rangetrace keeps the breaks as "\n  "): undone, so
// that a token split by a break is still found.
std::string unwrapped(std::string s) {
  for (std::size_t p; (p = s.find("\n  ")) != std::string::npos;) s.erase(p, 3);
  for (std::size_t p; (p = s.find('\n')) != std::string::npos;) s.erase(p, 1);
  return s;
}

}  // namespace

TEST_CASE("sandbox: the include check refuses writes and names that leave the include's directory") {
  const auto dir = test::fresh_dir("rangetrace", "inc_check");
  const std::string v = real(dir) + "/v.inc";
  struct Case {
    std::string text, want;
  };
  const Case cases[] = {
      {"#fopen F \"out.txt\" write\n", "line 1: #fopen ... write: an include may not write files"},
      {"\n#fopen F \"out.txt\" append\n", "line 2: #fopen ... append: an include may not write files"},
      {"#write (F, \"x\")\n", "line 1: 'write': an include may not write files"},
      {"#include \"/etc/passwd\"\n", "line 1: #include \"/etc/passwd\": an absolute path"},
      {"#include \"../secret.inc\"\n", "#include \"../secret.inc\": a '..' component"},
      {"#include \"sub/../../secret.inc\"\n", "a '..' component"},
      {"#declare N = \"x.inc\";\n#include N\n", "line 2: #include needs a literal file name"},
      {"#include concat(\"/et\", \"c/passwd\")\n", "line 1: #include needs a literal file name"},
      {"#fopen F concat(\"/etc/\", \"passwd\") read\n", "line 1: #fopen needs a literal file name"},
      {"#fopen F \"/etc/passwd\" read\n", "line 1: #fopen \"/etc/passwd\": an absolute path"},
      {"# /* a comment */ include \"/etc/passwd\"\n", "line 1: #include \"/etc/passwd\""},
      {"#declare P = pigment { image_map { png \"/etc/x.png\" } }\n",
       "'png' \"/etc/x.png\": an absolute path"},
      {"#declare P = pigment { image_map { png Name } }\n", "'png' needs a literal file name"},
      {"#include \"\\u002e\\u002e/x.inc\"\n", "a backslash"},
      {"#declare T = text { ttf \"../f.ttf\" \"hi\" 1, 0 }\n", "'ttf' \"../f.ttf\": a '..' component"},
      {"#if (file_exists(\"/etc/shadow\")) #end\n", "file_exists \"/etc/shadow\": an absolute path"},
      {"#include \".ssh/id_rsa\"\n", "a hidden (dot) component"},
      // POV-Ray's comments nest: the directive on line 2 is code.
      {"/* a /* b */ c */\n#include \"/x.inc\"\n", "line 2: #include \"/x.inc\""},
      // An escaped quote does not end a string.
      {"#declare S = \"a\\\"b\";\n#include \"/x.inc\"\n", "line 2: #include \"/x.inc\""},
  };
  for (const auto& c : cases) {
    INFO(c.text);
    const std::string msg = check_text(dir, c.text);
    CHECK_THAT(msg, Catch::StartsWith(v + ": ") && Catch::Contains(c.want));
  }
  // Text that only looks like a directive: in comments and strings.
  CHECK(check_text(dir,
                   "// #include \"/etc/passwd\"\n/* #fopen F \"/x\" write */\n"
                   "#declare S = \"#include \\\"/etc/passwd\\\"\";\n#declare Vehicle = box { 0, 1 }\n")
            .empty());
  // A macro of the standard includes that writes a file it is given: refused only when nothing
  // else confines POV-Ray.
  const std::string ps = "#include \"strings.inc\"\nParse_String(\"#declare A = 1;\")\n";
  CHECK(check_text(dir, ps, false).empty());
  CHECK_THAT(check_text(dir, ps, true), Catch::Contains("line 2: 'Parse_String'"));
  // An include directly in / would make everything its directory.
  CHECK_THROWS_WITH(check_user_include("/", "x.inc", false), Catch::Contains("in a directory of its own"));
}

TEST_CASE("sandbox: included files are checked too, and links out of the directory are refused") {
  const auto top = test::fresh_dir("rangetrace", "inc_nested");
  const auto dir = top / "model";
  fs::create_directories(dir / "parts");
  write_text(top / "outside.inc", "#declare Secret = 1;\n");
  write_text(dir / "parts" / "wheel.inc", "#declare W = 1;\n\n#fopen F \"/etc/passwd\" read\n");
  write_text(dir / "car.inc", "#include \"parts/wheel.inc\"\n#declare Vehicle = box { 0, 1 }\n");
  // The error names the included file and its line.
  CHECK_THROWS_WITH(check_user_include(real(dir), "car.inc", false),
                    Catch::StartsWith(real(dir) + "/parts/wheel.inc: line 3: #fopen \"/etc/passwd\""));
  // A symbolic link inside the directory that leads out of it.
  fs::create_symlink(top / "outside.inc", dir / "link.inc");
  write_text(dir / "car.inc", "#include \"link.inc\"\n");
  CHECK_THROWS_WITH(check_user_include(real(dir), "car.inc", false),
                    Catch::Contains("line 1: \"link.inc\" leads out of the include's directory"));

  // Accepted: the files POV-Ray may read are the include, what it includes (also without the
  // extension, as POV-Ray completes it), the files it reads and any file a string names.
  write_text(dir / "parts" / "wheel.inc", "#declare W = 1;\n");
  write_text(dir / "data.txt", "1, 2, 3\n");
  write_text(dir / "font.ttf", "not really a font\n");
  write_text(dir / "car.inc",
             "#include \"parts/wheel\"\n#fopen F \"data.txt\" read\n#read (F, A)\n#fclose F\n"
             "#declare Font = \"font.ttf\";\n#include \"colors.inc\"\n#declare Vehicle = box { 0, 1 }\n");
  const auto files = check_user_include(real(dir), "car.inc", false);
  const std::string d = real(dir);
  CHECK(files ==
        std::vector<std::string>{d + "/car.inc", d + "/data.txt", d + "/font.ttf", d + "/parts/wheel.inc"});
}

TEST_CASE("sandbox: in the jail POV-Ray cannot write or read outside its directory") {
  const auto dir = test::fresh_dir("rangetrace", "jail");
  if (!bwrap_usable(dir)) return;
  fs::create_directories(dir / "tmp");
  const std::string secret = "canopy_secret_token_7f3a";
  write_text(dir / "secret.txt", secret + "\n");
  const std::string outside = real(dir) + "/outside.txt";
  const std::string secret_path = real(dir) + "/secret.txt";
  ScopedEnv tmp("TMPDIR", real(dir / "tmp"));
  const std::string povray = "povray";
  const Staged none;  // canopy's own code: nothing checked, only the jail stands in the way

  // Runs `scene` (generated code, not checked) in a private directory; POV-Ray's message or "".
  auto run = [&](const std::string& scene) -> std::string {
    TempDir work;
    write_text(fs::path(work.path()) / "t.pov", "#version 3.7;\n" + scene);
    try {
      run_povray(povray, none, work.path(), {"-D", "-P", "-V", "+WT1", "+W1", "+H1", "-F", "+It.pov"},
                 "t.log");
    } catch (const common::Error& e) { return e.what(); }
    return "";
  };
  const std::string write = "#fopen Out \"" + outside + "\" write\n#write (Out, \"escaped\")\n#fclose Out\n";
  const std::string read = "#fopen In \"" + secret_path + "\" read\n#read (In, S)\n#fclose In\n";
  const std::string include = "#include \"" + secret_path + "\"\n";
  const std::string passwd = "#include \"/etc/passwd\"\n";
  {
    ScopedEnv mode("CANOPY_POVRAY_SANDBOX", "bwrap");
    CHECK_THAT(run(write), Catch::Contains("Cannot open user file"));
    CHECK_FALSE(test::exists(outside));
    for (const auto& scene : {read, include}) {
      const std::string msg = unwrapped(run(scene));
      CHECK_THAT(msg, Catch::Contains("POV-Ray failed") && !Catch::Contains(secret));
    }
    CHECK_THAT(unwrapped(run(passwd)),
               Catch::Contains("/etc/passwd") && !Catch::Contains("undeclared identifier"));
    // What the jail does not show (file_exists: POV-Ray's own probe of a path).
    std::string probe;
    const std::string home = std::getenv("HOME") ? std::getenv("HOME") : "/root";
    for (const std::string& p : std::vector<std::string>{"/etc/passwd", "/etc/hostname", "/root/.bashrc",
                                                         secret_path, home + "/.bashrc"}) {
      probe += "#if (file_exists(\"" + p + "\")) #error \"visible: " + p + "\" #end\n";
    }
    CHECK(run(probe).empty());
  }
  {
    // The same scenes unconfined (the documented opt-out): they do escape, so the checks above
    // can fail. The write lands in this test's own directory.
    ScopedEnv mode("CANOPY_POVRAY_SANDBOX", "off");
    CHECK(run(write).empty());
    CHECK(slurp(outside) == "escaped");
    CHECK_THAT(unwrapped(run(include)), Catch::Contains(secret));
  }
}

TEST_CASE("sandbox CLI: the round-3 reproducers are refused naming file and line; nothing escapes") {
  const auto dir = test::fresh_dir("rangetrace", "round3_pov");
  const auto probe = dir / "probe.txt";
  // sec-pov-write.inc writes /var/tmp/...: this copy writes into the test's directory instead.
  std::string w = slurp(data("sec-pov-write.inc"));
  const std::string target = "/var/tmp/canopy-fuzz-pov-write-probe.txt";
  REQUIRE(w.find(target) != std::string::npos);
  w.replace(w.find(target), target.size(), probe.string());
  write_text(dir / "sec-pov-write.inc", w);
  fs::copy_file(data("sec-pov-read.inc"), dir / "sec-pov-read.inc");
  std::string passwd_token;
  {
    std::ifstream p("/etc/passwd");
    std::getline(p, passwd_token, ':');
  }
  write_text(dir / "tile.scene",
             "extent = 10m\ntrees = 0\nbushes = 0\nflight_lines = 1\nheadings = 0deg\nlooks = 90deg\n"
             "spacing = 200mm\ncanopy_spacing = 200mm\nvehicle = sec-pov-write.inc 5m 5m 0deg\n");
  const std::string scene = q(data("scene-2views.scene"));
  for (const char* mode : {"auto", "off"}) {
    INFO("CANOPY_POVRAY_SANDBOX=" << mode);
    const std::string env = std::string("CANOPY_POVRAY_SANDBOX=") + mode + " ";
    std::string err;
    CHECK(test::sh(env + bin() + " --model " + q(dir / "sec-pov-write.inc") + " --scene " + scene +
                       " --size 64 -o " + q(dir / "w.pcd"),
                   dir / "err.txt", &err) == 1);
    CHECK_THAT(err, Catch::Contains(real(dir) + "/sec-pov-write.inc: line 3: #fopen ... write"));
    CHECK_FALSE(test::exists(probe));
    CHECK_FALSE(test::exists(dir / "w.pcd"));

    CHECK(test::sh(env + bin() + " --scene " + q(dir / "tile.scene") + " -o " + q(dir / "t.pcd"),
                   dir / "err.txt", &err) == 1);
    CHECK_THAT(err,
               Catch::Contains(dir.string() + "/tile.scene: line 9: vehicle model 'sec-pov-write.inc'") &&
                   Catch::Contains("line 3: #fopen ... write"));
    CHECK_FALSE(test::exists(probe));

    CHECK(test::sh(env + bin() + " --model " + q(dir / "sec-pov-read.inc") + " --scene " + scene +
                       " --size 64 -o " + q(dir / "r.pcd"),
                   dir / "err.txt", &err) == 1);
    CHECK_THAT(err, Catch::Contains(real(dir) +
                                    "/sec-pov-read.inc: line 3: #fopen \"/etc/passwd\": an absolute path"));
    CHECK_THAT(unwrapped(err), !Catch::Contains("undeclared identifier"));
    if (!passwd_token.empty()) CHECK_THAT(unwrapped(err), !Catch::Contains("'" + passwd_token + "'"));
    CHECK_FALSE(test::exists(dir / "r.pcd"));
  }
}

TEST_CASE("sandbox CLI: without a working bwrap a user include is refused, canopy's own models warn") {
  const auto dir = test::fresh_dir("rangetrace", "no_bwrap");
  // A bwrap that fails as it does where unprivileged user namespaces are disabled.
  write_text(
      dir / "bwrap",
      "#!/bin/sh\necho 'bwrap: No permissions to creating new namespace, likely because the kernel does not "
      "allow non-privileged user namespaces.' >&2\nexit 1\n");
  ::chmod((dir / "bwrap").c_str(), 0755);
  write_text(dir / "car.inc", "#declare Vehicle = box { <-2, 0, -1>, <2, 1.5, 1> }\n");
  const std::string common = " --scene unoccluded --size 16 --spacing 0.5m -o ";
  std::string err;
  for (const std::string& bwrap : {(dir / "bwrap").string(), (dir / "missing" / "bwrap").string()}) {
    INFO(bwrap);
    const std::string env = "CANOPY_BWRAP=" + q(bwrap) + " ";
    CHECK(test::sh(env + bin() + " --model " + q(dir / "car.inc") + common + q(dir / "u.pcd"),
                   dir / "err.txt", &err) == 1);
    CHECK_THAT(err, Catch::Contains("cannot confine POV-Ray: ") &&
                        Catch::Contains("a user include is only rendered confined") &&
                        Catch::Contains("CANOPY_POVRAY_SANDBOX=off"));
    CHECK_THAT(err, Catch::Contains(bwrap.find("missing") != std::string::npos
                                        ? "not found (install the Debian package bubblewrap)"
                                        : "No permissions to creating new namespace"));
    CHECK_FALSE(test::exists(dir / "u.pcd"));
    // canopy's own model: rendered unconfined with a warning (auto), refused when bwrap is
    // required.
    CHECK(test::sh(env + bin() + " --model sedan" + common + q(dir / "s.pcd"), dir / "err.txt", &err) == 0);
    CHECK_THAT(err, Catch::Contains("warning: POV-Ray runs unconfined: "));
    CHECK(test::sh(env + "CANOPY_POVRAY_SANDBOX=bwrap " + bin() + " --model sedan" + common + q(dir / "b.pcd"),
                   dir / "err.txt", &err) == 1);
    CHECK_THAT(err, Catch::Contains("cannot confine POV-Ray: "));
    CHECK_FALSE(test::exists(dir / "b.pcd"));
    // The explicit opt-out renders the include unconfined, with a warning.
    CHECK(test::sh(env + "CANOPY_POVRAY_SANDBOX=off " + bin() + " --model " + q(dir / "car.inc") + common +
                       q(dir / "o.pcd"),
                   dir / "err.txt", &err) == 0);
    CHECK_THAT(err, Catch::Contains("warning: POV-Ray runs unconfined (CANOPY_POVRAY_SANDBOX=off)"));
    fs::remove(dir / "s.pcd");
    fs::remove(dir / "o.pcd");
  }
  CHECK(test::sh("CANOPY_POVRAY_SANDBOX=jail " + bin() + " --model sedan" + common + q(dir / "x.pcd"),
                 dir / "err.txt", &err) == 2);
  CHECK_THAT(err, Catch::Contains("CANOPY_POVRAY_SANDBOX='jail': expected auto, bwrap or off"));
}

TEST_CASE("sandbox CLI: scans in the jail are byte-identical to unconfined ones") {
  const auto dir = test::fresh_dir("rangetrace", "jail_bytes");
  if (!bwrap_usable(dir)) return;
  fs::create_directories(dir / "inc");
  write_text(dir / "inc" / "half.inc", "#declare Half = 1;\n");
  write_text(dir / "inc" / "car.inc",
             "#include \"half.inc\"\n#declare Vehicle = union { box { <-2, 0, -Half>, <2, 1.5, Half> }\n"
             "  cylinder { <0, 1.5, 0>, <0, 2, 0>, 0.5 } }\n");
  write_text(
      dir / "tile.scene",
      "extent = 12m 10m\nterrain = rolling 1m 10m\ntrees = 200\nbushes = 100\nvehicle = sedan 4 5 20deg\n"
      "vehicle = inc/car.inc 9 5 100deg\nflight_lines = 1\nheadings = 0deg\nlooks = 70deg/0deg\n"
      "spacing = 150mm\ncanopy_spacing = 200mm\n");
  const std::string runs[] = {
      "--model sedan --scene circle --seed 7 --size 48 --spacing 0.25m",
      "--model family:wheel-loader:5 --scene flyby --seed 3 --size 32 --spacing 0.4m",
      "--model " + q(dir / "inc" / "car.inc") + " --scene unoccluded --size 32 --spacing 0.3m --heading 30",
      "--scene " + q(dir / "tile.scene") + " --seed 4",
  };
  int k = 0;
  for (const auto& args : runs) {
    INFO(args);
    const auto jailed = dir / ("jailed" + std::to_string(k) + ".pcd");
    const auto plain = dir / ("plain" + std::to_string(k) + ".pcd");
    std::string err;
    REQUIRE(test::sh("CANOPY_POVRAY_SANDBOX=bwrap " + bin() + " -q " + args + " -o " + q(jailed),
                     dir / "err.txt", &err) == 0);
    REQUIRE(test::sh("CANOPY_POVRAY_SANDBOX=off " + bin() + " -q " + args + " -o " + q(plain),
                     dir / "err.txt", &err) == 0);
    const std::string a = slurp(jailed), b = slurp(plain);
    CHECK(a.size() > 1000);
    CHECK(a == b);
    ++k;
  }
}
