// The hardened command line of the tool binaries (issue 12): stray words and mistyped options,
// out-of-range values, sanity warnings, outputs checked before the work, stdout write errors,
// FIFOs and devices written through, tools with two or more outputs atomic as a whole (also
// under SIGINT), and truncated PNGs refused by `figures grid` instead of crashing it.
#include <fcntl.h>
#include <png.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "canopy/documents/experiment_manifest.h"
#include "canopy/documents/match_result.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/ply.h"
#include "canopy/documents/segment_graph.h"
#include "support/cli.h"

namespace fs = std::filesystem;
using canopy::test::fresh_dir;
using canopy::test::sh;

namespace {

const std::string kBin = CANOPY_BIN_DIR;

std::string bin(const std::string& tool) { return kBin + "/" + tool; }

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

int count_files(const fs::path& dir) {
  int n = 0;
  for (auto it = fs::directory_iterator(dir); it != fs::directory_iterator(); ++it) ++n;
  return n;
}

// A gently curved 40 x 40 patch of points, 20 mm apart.
void write_patch(const fs::path& path) {
  canopy::formats::PointCloud c;
  for (const char* f : {"x", "y", "z"}) c.add(f, canopy::formats::kFloat32);
  c.resize(1600);
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 40; ++j) {
      const std::size_t k = static_cast<std::size_t>(40 * i + j);
      c.col("x")[k] = 0.02 * i;
      c.col("y")[k] = 0.02 * j;
      c.col("z")[k] = 0.05 * std::sin(0.1 * i);
    }
  }
  canopy::formats::write_pcd(c, path.string());
}

// A roof: two 8 x 8 grids meeting at a right angle along x = 0.
void write_roof(const fs::path& path) {
  canopy::formats::Mesh m;
  auto& v = m.vertices;
  for (const char* f : {"x", "y", "z"}) v.add(f, canopy::formats::kFloat32);
  const int n = 8;
  v.resize(static_cast<std::size_t>(2 * (n + 1) * (n + 1)));
  for (int side = 0; side < 2; ++side) {
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; j <= n; ++j) {
        const std::size_t k = static_cast<std::size_t>(side * (n + 1) * (n + 1) + i * (n + 1) + j);
        const double s = 0.1 * i;
        v.col("x")[k] = side == 0 ? -s : s;
        v.col("y")[k] = 0.1 * j;
        v.col("z")[k] = 1.0 - s;
      }
    }
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const int b = side * (n + 1) * (n + 1), a = b + i * (n + 1) + j;
        m.faces.push_back({a, a + 1, a + n + 2});
        m.faces.push_back({a, a + n + 2, a + n + 1});
      }
    }
  }
  canopy::formats::write_ply(m, path.string());
}

bool make_char_device(const fs::path& path, unsigned major, unsigned minor) {
  return mknod(path.c_str(), S_IFCHR | 0666, makedev(major, minor)) == 0;
}

bool is_char_device(const fs::path& p) {
  struct stat st {};
  return lstat(p.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}

}  // namespace

TEST_CASE("a stray word is answered with 'use -i', a mistyped option with 'did you mean'") {
  const fs::path d = fresh_dir("cli", "words");
  std::string err;
  CHECK(sh(bin("fitvox") + " scan.pcd", d / "err", &err) == 2);
  CHECK_THAT(err, Catch::Contains("use -i scan.pcd"));
  CHECK(sh(bin("ncut") + " --radus 5mm -i m.ply", d / "err", &err) == 2);
  CHECK_THAT(err, Catch::Contains("did you mean --radius?"));
  CHECK(sh(bin("addnoise") + " --sigam 8mm -i s.pcd", d / "err", &err) == 2);
  CHECK_THAT(err, Catch::Contains("did you mean --sigma?"));
  // A mistyped option that leaves a required one missing is still named; so is a subcommand.
  CHECK(sh(bin("gmatch") + " -i a.json --modelbse mb", d / "err", &err) == 2);
  CHECK_THAT(err, Catch::Contains("did you mean --modelbase?"));
  CHECK(sh(bin("figures") + " gird -o x.png", d / "err", &err) == 2);
  CHECK_THAT(err, Catch::Contains("unknown subcommand 'gird': did you mean grid?"));
  CHECK(sh(bin("figures") + " grid --cosl 2 -o x.png a.png", d / "err", &err) == 2);
  CHECK_THAT(err, Catch::Contains("did you mean --cols?"));
  // Tools that ignore --threads no longer accept it (fitvox uses it).
  CHECK(sh(bin("addnoise") + " --threads 2 -i s.pcd", d / "err", &err) == 2);
  CHECK(sh(bin("detect") + " --threads 2 -i s.pcd -o c", d / "err", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--threads"));
  CHECK(sh(bin("verify") + " --threads 2 -i m.json", d / "err", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--threads"));
  CHECK(sh(bin("fitvox") + " --help > " + q(d / "help"), d / "err", &err) == 0);
}

TEST_CASE("--pcd-encoding writes binary_compressed and ascii PCD with the same points") {
  const fs::path d = fresh_dir("cli", "pcd_encoding");
  write_patch(d / "scan.pcd");
  std::string err;
  for (const std::string tool : {"addnoise", "fitvox"}) {
    const std::string base = bin(tool) + " -q -i " + q(d / "scan.pcd");
    REQUIRE(sh(base + " -o " + q(d / (tool + "-b.pcd")), d / "err", &err) == 0);
    REQUIRE(sh(base + " --pcd-encoding binary_compressed -o " + q(d / (tool + "-c.pcd")), d / "err", &err) == 0);
    REQUIRE(sh(base + " --pcd-encoding ascii -o " + q(d / (tool + "-a.pcd")), d / "err", &err) == 0);
    CHECK_THAT(slurp(d / (tool + "-c.pcd")), Catch::Contains("\nDATA binary_compressed\n"));
    CHECK_THAT(slurp(d / (tool + "-a.pcd")), Catch::Contains("\nDATA ascii\n"));
    const auto b = canopy::formats::read_pcd((d / (tool + "-b.pcd")).string());
    for (const std::string v : {"c", "a"}) {
      const auto o = canopy::formats::read_pcd((d / (tool + "-" + v + ".pcd")).string());
      REQUIRE(o.size() == b.size());
      REQUIRE(o.names() == b.names());
      for (std::size_t c = 0; c < b.names().size(); ++c) {
        for (std::size_t i = 0; i < b.size(); ++i) {
          // Ascii prints float32 columns with enough digits to round-trip them.
          CHECK(static_cast<float>(o.col(c)[i]) == static_cast<float>(b.col(c)[i]));
        }
      }
    }
    CHECK(sh(base + " --pcd-encoding lzf -o " + q(d / (tool + "-x.pcd")), d / "err", &err) == 2);
    CHECK_THAT(err, Catch::Contains("--pcd-encoding"));
    CHECK_FALSE(fs::exists(d / (tool + "-x.pcd")));
  }
}

TEST_CASE("values out of an option's range are usage errors naming the option, before any output") {
  const fs::path d = fresh_dir("cli", "ranges");
  write_patch(d / "scan.pcd");
  write_roof(d / "roof.ply");
  const std::string scan = " -i " + q(d / "scan.pcd"), out = " -o " + q(d / "out.pcd");
  std::string err;
  CHECK(sh(bin("ncut") + " --radius 1e-9 -i " + q(d / "roof.ply") + " -o " + q(d / "g.json"), d / "err",
           &err) == 2);
  CHECK_THAT(err, Catch::Contains("--radius"));
  CHECK(sh(bin("fitvox") + " --voxel 1e-300" + scan + out, d / "err", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--voxel"));
  CHECK(sh(bin("addnoise") + " --sigma 1e300" + scan + out, d / "err", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--sigma"));
  CHECK(sh(bin("addnoise") + " --sigma 0x10mm" + scan + out, d / "err", &err) == 2);
  CHECK(sh(bin("addnoise") + " --sigma 4mm --seed -1" + scan + out, d / "err", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--seed"));
  CHECK(sh(bin("addnoise") + " --sigma 4mm --seed 0x7" + scan + out, d / "err", &err) == 2);
  CHECK_FALSE(fs::exists(d / "out.pcd"));
  CHECK_FALSE(fs::exists(d / "g.json"));
  // The valid neighbours of those values run.
  CHECK(sh(bin("addnoise") + " -q --sigma 4mm --seed 18446744073709551615" + scan + out, d / "err", &err) == 0);
  CHECK(fs::exists(d / "out.pcd"));
}

TEST_CASE("sanity warnings: lengths over 1 m, cocone given raw points") {
  const fs::path d = fresh_dir("cli", "warnings");
  write_patch(d / "scan.pcd");
  std::string err;
  CHECK(sh(bin("addnoise") + " -q --sigma 8 --seed 1 -i " + q(d / "scan.pcd") + " -o " + q(d / "n.pcd"),
           d / "err", &err) == 0);
  CHECK_THAT(err, Catch::Contains("warning") && Catch::Contains("bare numbers are metres") &&
                      Catch::Contains("did you mean 8mm?"));
  sh(bin("fitvox") + " -q --voxel 2 -i " + q(d / "scan.pcd") + " -o " + q(d / "s.pcd"), d / "err", &err);
  CHECK_THAT(err, Catch::Contains("warning: --voxel 2 is 2m"));
  CHECK(sh(bin("addnoise") + " -q --sigma 8mm --seed 1 -i " + q(d / "scan.pcd") + " -o " + q(d / "n.pcd"),
           d / "err", &err) == 0);
  CHECK(err.empty());
  sh(bin("cocone") + " -q -i " + q(d / "scan.pcd") + " -o " + q(d / "m.ply"), d / "err", &err);
  CHECK_THAT(err, Catch::Contains("warning") && Catch::Contains("not fitvox samples"));
}

TEST_CASE("an output directory that does not exist is reported before the input is read") {
  const fs::path d = fresh_dir("cli", "outdir");
  std::ofstream(d / "garbage.pcd") << "not a point cloud";
  std::string err;
  CHECK(sh(bin("fitvox") + " -i " + q(d / "garbage.pcd") + " -o " + q(d / "nodir" / "s.pcd"), d / "err",
           &err) == 1);
  CHECK_THAT(err, Catch::Contains((d / "nodir").string()) && Catch::Contains("does not exist"));
  CHECK_THAT(err, !Catch::Contains("garbage.pcd"));
  CHECK(sh(bin("ncut") + " -i " + q(d / "garbage.pcd") + " --colored " + q(d / "nodir" / "c.ply") + " -o " +
               q(d / "g.json"),
           d / "err", &err) == 1);
  CHECK_THAT(err, Catch::Contains("nodir"));
}

TEST_CASE("a full stdout is reported as '<stdout>: write failed'") {
  const fs::path d = fresh_dir("cli", "stdout");
  write_patch(d / "scan.pcd");
  std::string err;
  // A file size limit of 1 KiB on a temporary file stands in for a full disk (SIGXFSZ ignored,
  // so write() fails with EFBIG instead of killing the tool).
  const int rc = sh("bash -c \"trap '' XFSZ; ulimit -f 1; exec " + bin("addnoise") + " -q --sigma 0 -i " +
                        q(d / "scan.pcd") + " -o - > " + q(d / "out.pcd") + "\"",
                    d / "err", &err);
  CHECK(rc == 1);
  CHECK_THAT(err, Catch::Contains("<stdout>: write failed"));
  CHECK_THAT(err, !Catch::Contains("<stdin>"));
}

TEST_CASE("a FIFO and a character device given as -o are written through and keep their type") {
  const fs::path d = fresh_dir("cli", "special");
  write_patch(d / "scan.pcd");
  const std::string run = bin("addnoise") + " -q --sigma 0 -i " + q(d / "scan.pcd");
  std::string err;
  REQUIRE(sh(run + " -o " + q(d / "plain.pcd"), d / "err", &err) == 0);
  REQUIRE(mkfifo((d / "fifo.pcd").c_str(), 0600) == 0);
  CHECK(sh("timeout 10 cat " + q(d / "fifo.pcd") + " > " + q(d / "got") + " & " + run + " -o " +
               q(d / "fifo.pcd") + "; wait",
           d / "err", &err) == 0);
  CHECK(slurp(d / "got") == slurp(d / "plain.pcd"));
  struct stat st {};
  REQUIRE(lstat((d / "fifo.pcd").c_str(), &st) == 0);
  CHECK(S_ISFIFO(st.st_mode));
  fs::create_symlink("plain.pcd", d / "link.pcd");
  CHECK(sh(bin("addnoise") + " -q --sigma 1mm --seed 3 -i " + q(d / "scan.pcd") + " -o " + q(d / "link.pcd"),
           d / "err", &err) == 0);
  CHECK(fs::is_symlink(d / "link.pcd"));
  CHECK(slurp(d / "plain.pcd") != slurp(d / "got"));  // the link's target was replaced
  if (!make_char_device(d / "null.pcd", 1, 3)) {
    WARN("cannot create device nodes here (not root): device case not run");
    return;
  }
  CHECK(sh(run + " -o " + q(d / "null.pcd"), d / "err", &err) == 0);
  CHECK(is_char_device(d / "null.pcd"));
}

TEST_CASE("ncut: -o and --colored naming one file is a usage error") {
  const fs::path d = fresh_dir("cli", "ncut_same");
  write_roof(d / "roof.ply");
  const std::string run = bin("ncut") + " -q -i " + q(d / "roof.ply");
  std::string err;
  CHECK(sh(run + " -o " + q(d / "x.json") + " --colored " + q(d / "x.json"), d / "err", &err) == 2);
  CHECK_THAT(err, Catch::Contains("same file"));
  CHECK(sh(run + " -o " + q(d / "x.json") + " --colored " + q(d / "." / "x.json"), d / "err", &err) == 2);
  fs::create_symlink("x.json", d / "alias.json");
  CHECK(sh(run + " -o " + q(d / "x.json") + " --colored " + q(d / "alias.json"), d / "err", &err) == 2);
  CHECK(sh(run + " --colored -", d / "err", &err) == 2);  // -o defaults to stdout too
  CHECK_FALSE(fs::exists(d / "x.json"));
  CHECK(sh(run + " -o " + q(d / "x.json") + " --colored " + q(d / "c.ply"), d / "err", &err) == 0);
  CHECK(fs::exists(d / "x.json"));
  CHECK(fs::exists(d / "c.ply"));
}

TEST_CASE("ncut: the coloured PLY is not left when the JSON cannot be written") {
  const fs::path d = fresh_dir("cli", "ncut_atomic");
  write_roof(d / "roof.ply");
  if (!make_char_device(d / "full.json", 1, 7)) {
    WARN("cannot create device nodes here (not root): not run");
    return;
  }
  std::string err;
  CHECK(sh(bin("ncut") + " -q -i " + q(d / "roof.ply") + " -o " + q(d / "full.json") + " --colored " +
               q(d / "c.ply"),
           d / "err", &err) == 1);
  CHECK_THAT(err, Catch::Contains("write failed"));
  CHECK_FALSE(fs::exists(d / "c.ply"));
  CHECK(is_char_device(d / "full.json"));
  CHECK(count_files(d) == 3);  // roof.ply, full.json, err: no temporary file
}

TEST_CASE("ncut: SIGINT while committing leaves neither output nor a temporary file") {
  const fs::path d = fresh_dir("cli", "ncut_signal");
  write_roof(d / "roof.ply");
  REQUIRE(mkfifo((d / "seg.json").c_str(), 0600) == 0);
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    // -o is a FIFO nobody reads: the commit creates the coloured PLY's temporary file, then
    // waits to open the FIFO.
    const int null_in = open("/dev/null", O_RDONLY);
    dup2(null_in, STDIN_FILENO);
    const std::string tool = bin("ncut"), in = (d / "roof.ply").string(), out = (d / "seg.json").string(),
                      colored = (d / "c.ply").string();
    execl(tool.c_str(), tool.c_str(), "-q", "-i", in.c_str(), "-o", out.c_str(), "--colored", colored.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  bool temp_seen = false;
  for (int i = 0; i < 1000 && !temp_seen; ++i) {  // up to 10 s
    temp_seen = count_files(d) == 3;
    if (!temp_seen) usleep(10000);
  }
  CHECK(temp_seen);
  kill(pid, SIGINT);
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  CHECK((WIFSIGNALED(status) && WTERMSIG(status) == SIGINT));
  CHECK(count_files(d) == 2);  // roof.ply and the FIFO
  CHECK_FALSE(fs::exists(d / "c.ply"));
}

namespace {

// The smallest experiment report() accepts: one object, scene and noise level.
void write_experiment(const fs::path& out) {
  namespace cf = canopy::documents;
  const fs::path trial = out / "sedan" / "circle" / "noise-0";
  fs::create_directories(trial);
  cf::SegmentGraph g;
  g.provenance = {"ncut", "test", {}, {"mesh.ply"}};
  g.mesh = "mesh.ply";
  cf::Segment s;
  s.segment_id = 0;
  s.vertex_count = 3;
  s.area = 1;
  s.radii = {1, 0.5, 0.01};
  s.thickness = 0.01;
  s.elongation = 0.5;
  s.normal = {0, 0, 1};
  s.label = 1;
  s.label_purity = 1;
  s.vertices = {0, 1, 2};
  g.segments.push_back(s);
  cf::write_segment_graph(g, (trial / "segments.json").string());
  cf::MatchResult m;
  m.provenance = {"gmatch", "test", {}, {"segments.json"}};
  m.object = "segments.json";
  m.error_form = "bounded";
  cf::ModelScore ms;
  ms.model = "sedan";
  ms.score = 0.9;
  ms.rank = 1;
  m.models.push_back(ms);
  cf::write_match_result(m, (trial / "match.json").string());
  std::ofstream(out / "experiment.txt") << "trial sedan circle 0 " << trial.string() << "\n";
}

}  // namespace

TEST_CASE("report: its six outputs appear together or not at all") {
  const fs::path d = fresh_dir("cli", "report");
  write_experiment(d / "out");
  const std::string run = bin("report") + " -q --manifest " + q(d / "out" / "experiment.txt") + " --results ";
  std::string err;
  // A results directory that does not exist: reported before anything is read.
  CHECK(sh(run + q(d / "nores"), d / "err", &err) == 1);
  CHECK_THAT(err, Catch::Contains("nores"));
  fs::create_directories(d / "res");
  // Noise levels are whole decimal millimetres ("0x10" used to be read as 0, "8mm" as 8): a
  // manifest that says otherwise is refused, naming the file and the line.
  const std::string trial = (d / "out" / "sedan" / "circle" / "noise-0").string();
  for (const char* noise : {"0x10", "0mm", "-1"}) {
    std::ofstream(d / "bad.txt") << "# a comment\ntrial sedan circle " << noise << " " << trial << "\n";
    CHECK(sh(bin("report") + " -q --manifest " + q(d / "bad.txt") + " --results " + q(d / "res"), d / "err",
             &err) == 1);
    CHECK_THAT(err, Catch::Contains("bad.txt") && Catch::Contains("line 2") && Catch::Contains(noise));
  }
  CHECK(count_files(d / "res") == 0);
  REQUIRE(sh(run + q(d / "res"), d / "err", &err) == 0);
  CHECK(count_files(d / "res") == 6);  // report.md and five CSVs
  fs::remove_all(d / "res");
  fs::create_directories(d / "res");
  if (!make_char_device(d / "res" / "report.md", 1, 7)) {
    WARN("cannot create device nodes here (not root): failing report.md not tested");
    return;
  }
  CHECK(sh(run + q(d / "res"), d / "err", &err) == 1);
  CHECK_THAT(err, Catch::Contains("report.md") && Catch::Contains("write failed"));
  CHECK(count_files(d / "res") == 1);  // no CSV beside the failed report
  CHECK(is_char_device(d / "res" / "report.md"));
}

TEST_CASE("figures grid: truncated and oversized PNGs are errors naming the file, not crashes") {
  const fs::path d = fresh_dir("cli", "png");
  // A real 64 x 48 RGB PNG with varied pixels (so its compressed data spans many bytes).
  std::vector<std::uint8_t> pixels(64 * 48 * 3);
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<std::uint8_t>((i * 7919) % 251);
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  img.width = 64;
  img.height = 48;
  img.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  REQUIRE(png_image_write_to_memory(&img, nullptr, &size, 0, pixels.data(), 0, nullptr) != 0);
  std::string png(size, '\0');
  REQUIRE(png_image_write_to_memory(&img, &png[0], &size, 0, pixels.data(), 0, nullptr) != 0);
  png.resize(size);
  std::ofstream(d / "whole.png", std::ios::binary) << png;
  std::string err;
  const std::string grid = bin("figures") + " grid -q --cols 1 -o " + q(d / "grid.png") + " ";
  REQUIRE(sh(grid + q(d / "whole.png"), d / "err", &err) == 0);
  fs::remove(d / "grid.png");
  for (std::size_t keep : {std::size_t{8}, std::size_t{33}, std::size_t{100}, png.size() / 2, png.size() - 40}) {
    const fs::path cut = d / ("cut-" + std::to_string(keep) + ".png");
    std::ofstream(cut, std::ios::binary) << png.substr(0, keep);
    INFO("truncated to " << keep << " of " << png.size() << " bytes");
    CHECK(sh(grid + q(cut), d / "err", &err) == 1);
    CHECK_THAT(err, Catch::Contains(cut.string()));
    CHECK_FALSE(fs::exists(d / "grid.png"));
  }
  // A header claiming 100000 x 100000 pixels: refused before any allocation.
  std::string huge = png;
  const unsigned char dims[8] = {0, 1, 0x86, 0xA0, 0, 1, 0x86, 0xA0};
  std::memcpy(&huge[16], dims, 8);
  const unsigned long crc = crc32(crc32(0, nullptr, 0), reinterpret_cast<const unsigned char*>(&huge[12]), 17);
  for (int k = 0; k < 4; ++k) huge[29 + k] = static_cast<char>((crc >> (24 - 8 * k)) & 0xff);
  std::ofstream(d / "huge.png", std::ios::binary) << huge;
  CHECK(sh(grid + q(d / "huge.png"), d / "err", &err) == 1);
  CHECK_THAT(err, Catch::Contains("huge.png") && Catch::Contains("8192"));
}
