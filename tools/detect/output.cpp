#include "detect/output.h"

#include <fcntl.h>
#include <openssl/evp.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <system_error>
#include <vector>

#include "canopy/common/atomic_dir.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/documents/candidates.h"
#include "canopy/documents/detect_manifest.h"
#include "canopy/formats/provenance.h"
#include "detect/crops.h"

namespace canopy::detect {
namespace {

namespace fs = std::filesystem;
using common::DataError;

constexpr const char* kIndexName = "index.json";
// Inside a temporary directory while it is being built (created first, removed last).
constexpr const char* kPartialMarker = ".detect-partial";
constexpr std::uintmax_t kMaxManifestBytes = 64u << 20;

std::string errno_text(int e) { return std::strerror(e); }

// ---------------------------------------------------------------------------------------
// SHA-256 (OpenSSL).

struct MdCtxFree {
  void operator()(EVP_MD_CTX* c) const { EVP_MD_CTX_free(c); }
};

std::string hex(const unsigned char* md, unsigned len) {
  static const char* digits = "0123456789abcdef";
  std::string out(2 * len, '0');
  for (unsigned i = 0; i < len; ++i) {
    out[2 * i] = digits[md[i] >> 4];
    out[2 * i + 1] = digits[md[i] & 15];
  }
  return out;
}

// An incremental SHA-256: update() with the bytes in order, then finish() (hex digits).
class Sha256 {
 public:
  Sha256() : ctx_(EVP_MD_CTX_new()) {
    if (!ctx_ || EVP_DigestInit_ex(ctx_.get(), EVP_sha256(), nullptr) != 1) fail();
  }
  void update(const char* p, std::size_t n) {
    if (EVP_DigestUpdate(ctx_.get(), p, n) != 1) fail();
  }
  std::string finish() {
    unsigned char md[EVP_MAX_MD_SIZE];
    unsigned len = 0;
    if (EVP_DigestFinal_ex(ctx_.get(), md, &len) != 1) fail();
    return hex(md, len);
  }

 private:
  [[noreturn]] static void fail() { throw common::Error("detect: SHA-256 failed (OpenSSL)"); }
  std::unique_ptr<EVP_MD_CTX, MdCtxFree> ctx_;
};

std::string sha256(const std::string& bytes) {
  Sha256 h;
  h.update(bytes.data(), bytes.size());
  return h.finish();
}

// The SHA-256 of a file's content and its size; nullopt when it cannot be read.
std::optional<std::pair<std::string, std::uintmax_t>> sha256_file(const fs::path& p) {
  Sha256 h;
  const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) return std::nullopt;
  std::vector<char> buf(1 << 20);
  std::uintmax_t size = 0;
  for (;;) {
    const ssize_t n = ::read(fd, buf.data(), buf.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ::close(fd);
      if (n < 0) return std::nullopt;
      return std::make_pair(h.finish(), size);
    }
    size += std::uintmax_t(n);
    h.update(buf.data(), std::size_t(n));
  }
}

// ---------------------------------------------------------------------------------------
// What -o names.

struct Target {
  std::string given;  // as given, for messages
  std::string via;    // " (the symbolic link points to '…')" or ""
  fs::path path;      // links followed
  fs::path parent;    // its directory ("." for a bare name)
  std::string name;   // its file name
};

// Follows a chain of symbolic links (at most 40) to the path it names, which may not exist.
fs::path follow_links(const std::string& given, fs::path p) {
  for (int hops = 0;; ++hops) {
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p;
    if (hops >= 40) throw DataError(given, "too many levels of symbolic links");
    std::error_code ec;
    const fs::path target = fs::read_symlink(p, ec);
    if (ec) throw DataError(given, "cannot read symbolic link: " + ec.message());
    p = target.is_absolute() || !p.has_parent_path() ? target : p.parent_path() / target;
  }
}

Target resolve_target(const std::string& dir) {
  if (dir.empty() || dir == "-") throw common::UsageError("-o/--output must name a directory");
  Target t;
  t.given = dir;
  auto normal = [](fs::path p) {
    p = p.lexically_normal();
    if (!p.has_filename() && p.has_parent_path() && p != p.root_path()) p = p.parent_path();  // "cands/"
    return p;
  };
  const fs::path plain = normal(dir);
  const fs::path p = normal(follow_links(dir, plain));
  if (p != plain) t.via = " (the symbolic link points to '" + p.string() + "')";
  const std::string name = p.filename().string();
  if (name.empty() || name == "." || name == "..") {
    throw common::UsageError("-o must name a directory to create or replace, not '" + dir + "'");
  }
  t.path = p;
  t.name = name;
  t.parent = p.has_parent_path() ? p.parent_path() : fs::path(".");
  struct stat st {};
  if (::stat(t.parent.c_str(), &st) != 0) {
    throw DataError(
        dir, "directory '" + t.parent.string() + "' does not exist" + t.via + " (detect does not create it)");
  }
  if (!S_ISDIR(st.st_mode)) throw DataError(dir, "'" + t.parent.string() + "' is not a directory" + t.via);
  if (::access(t.parent.c_str(), W_OK | X_OK) != 0) {
    throw DataError(dir, "cannot write in directory '" + t.parent.string() + "': " + errno_text(errno) + t.via);
  }
  return t;
}

// "a, b, c/ and 4 more".
std::string name_list(std::vector<std::string> names) {
  std::sort(names.begin(), names.end());
  std::string out;
  const std::size_t shown = std::min<std::size_t>(names.size(), 6);
  for (std::size_t i = 0; i < shown; ++i) out += (i ? ", " : "") + names[i];
  if (names.size() > shown) out += " and " + std::to_string(names.size() - shown) + " more";
  return out;
}

// A plain file name: no directory part, not hidden, not "." or "..".
bool plain_name(const std::string& n) {
  return !n.empty() && n.size() < 256 && n[0] != '.' && n.find('/') == std::string::npos &&
         n.find('\0') == std::string::npos;
}

// A name the chain (mk/scenes.mk: stagerun, fitvox, cocone, ncut, gmatch, verify, baseline)
// writes in a candidate's directory: <stage>.<pcd|ply|json|log|time>, optionally + ".tmp"
// (stagerun's .time.tmp, AtomicOutput's .<stem>.tmp<pid>-<n>.<ext>).
bool chain_file_name(std::string n) {
  if (n.size() > 4 && n.compare(n.size() - 4, 4, ".tmp") == 0) n.resize(n.size() - 4);
  for (const char* ext : {".pcd", ".ply", ".json", ".log", ".time"}) {
    const std::size_t e = std::strlen(ext);
    if (n.size() > e && n.compare(n.size() - e, e, ext) == 0) return n.find('/') == std::string::npos;
  }
  return false;
}

struct Listed {
  std::uintmax_t bytes = 0;
  std::string sha256;  // empty for an index-only (older) output
};

// The files a previous output lists (name -> size and hash), from its manifest or, for an
// output written before manifests, from its index. nullopt when it has neither; a problem
// text in *why when one is there but is not detect's.
struct Listing {
  bool manifest = false;
  std::map<std::string, Listed> files;
};

// The text of a manifest or index of a previous output; nullopt (and why) when it cannot be
// read or is beyond kMaxManifestBytes.
std::optional<std::string> read_small(const fs::path& p, std::string* why) {
  std::error_code ec;
  const auto size = fs::file_size(p, ec);
  if (ec || size > kMaxManifestBytes) {
    *why = ec ? ec.message() : "too large";
    return std::nullopt;
  }
  try {
    return common::read_file(p.string());
  } catch (const std::exception& e) {
    *why = e.what();
    return std::nullopt;
  }
}

std::optional<Listing> read_manifest(const fs::path& dir, std::string* why) {
  const fs::path p = dir / kManifestName;
  auto bad = [&](const std::string& w) {
    *why = std::string(kManifestName) + " is not detect's (" + w + ")";
    return std::nullopt;
  };
  std::string err;
  const std::optional<std::string> text = read_small(p, &err);
  if (!text) return bad(err);
  documents::DetectManifest m;
  try {
    m = documents::read_detect_manifest(*text, p.string());
  } catch (const common::DataError& e) { return bad(e.what()); }
  Listing l;
  l.manifest = true;
  for (const documents::ManifestFile& f : m.files) {
    if (!plain_name(f.name) || f.name == kManifestName) return bad("file name '" + f.name + "'");
    l.files[f.name] = Listed{f.bytes, f.sha256};
  }
  if (!l.files.count(kIndexName)) return bad("index.json not listed");
  return l;
}

// An output of detect from before manifests: index.json of format canopy.candidates written by
// detect (documents/candidates.h reads it); it names index.json, the candidates' files and
// classes.ply.
std::optional<Listing> read_legacy_index(const fs::path& dir) {
  const fs::path p = dir / kIndexName;
  std::string err;
  const std::optional<std::string> text = read_small(p, &err);
  if (!text) return std::nullopt;
  documents::Candidates index;
  try {
    index = documents::read_candidates(*text, p.string());
  } catch (const common::DataError&) { return std::nullopt; }
  if (index.written_by() != "detect") return std::nullopt;
  Listing l;
  l.files[kIndexName] = {};
  if (!index.classes.empty()) {
    if (!plain_name(index.classes)) return std::nullopt;
    l.files[index.classes] = {};
  }
  for (const documents::Candidate& c : index.candidates) {
    if (!plain_name(c.file)) return std::nullopt;
    l.files[c.file] = {};
  }
  return l;
}

// The problems that keep detect from replacing the existing directory `t.path` (empty: it may
// be replaced). `input` is the tile's real path ("" for stdin).
std::vector<std::string> replace_problems(const Target& t, const std::string& input) {
  std::vector<std::string> problems;
  std::vector<std::string> entries;  // "name" or "name/"
  std::error_code ec;
  for (fs::directory_iterator it(t.path, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    entries.push_back(it->is_directory(ec) && !it->is_symlink(ec) ? n + "/" : n);
  }
  if (ec) return {"cannot list it: " + ec.message()};
  if (!input.empty()) {
    char real[PATH_MAX];
    if (::realpath(t.path.c_str(), real) != nullptr) {
      const std::string root = std::string(real) + "/";
      if (input.compare(0, root.size(), root) == 0) {
        problems.push_back("it holds the input tile " + input);
      }
    }
  }
  if (entries.empty()) return problems;
  std::string why;
  std::optional<Listing> listing;
  if (fs::exists(fs::symlink_status(t.path / kManifestName))) {
    listing = read_manifest(t.path, &why);
  } else {
    listing = read_legacy_index(t.path);
    if (!listing) why = "it has no manifest.json and no index.json written by detect";
  }
  if (!listing) {
    problems.push_back(why + "; it holds " + name_list(entries));
    return problems;
  }
  std::vector<std::string> foreign, changed, missing;
  std::set<std::string> seen;
  for (const std::string& e : entries) {
    const bool is_dir = e.back() == '/';
    const std::string n = is_dir ? e.substr(0, e.size() - 1) : e;
    if (!is_dir && listing->manifest && n == kManifestName) continue;
    const auto f = listing->files.find(n);
    if (!is_dir && f != listing->files.end()) {
      seen.insert(n);
      const fs::path p = t.path / n;
      if (!fs::is_regular_file(fs::symlink_status(p))) {
        changed.push_back(n + " (not a regular file)");
        continue;
      }
      if (!listing->manifest) continue;
      const auto h = sha256_file(p);
      if (!h) {
        changed.push_back(n + " (unreadable)");
      } else if (h->second != f->second.bytes || h->first != f->second.sha256) {
        changed.push_back(n);
      }
      continue;
    }
    if (is_dir && listing->files.count(n + ".pcd")) {
      // The chain's directory of candidate n: only chain outputs, no subdirectories or links.
      std::vector<std::string> odd;
      for (fs::directory_iterator it(t.path / n, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string m = it->path().filename().string();
        if (!fs::is_regular_file(it->symlink_status(ec)) || !chain_file_name(m)) odd.push_back(n + "/" + m);
      }
      if (ec) odd.push_back(n + "/ (cannot list it: " + ec.message() + ")");
      foreign.insert(foreign.end(), odd.begin(), odd.end());
      continue;
    }
    foreign.push_back(e);
  }
  for (const auto& [n, f] : listing->files) {
    if (!seen.count(n)) missing.push_back(n);
  }
  const std::string source = listing->manifest ? "its manifest.json" : "its index.json";
  if (!foreign.empty())
    problems.push_back("it holds " + name_list(foreign) + ", which detect did not write (not in " + source +
                       ")");
  const auto them = [](const std::vector<std::string>& v) { return v.size() == 1 ? " it" : " them"; };
  if (!changed.empty()) {
    problems.push_back(name_list(changed) + " changed since detect wrote" + them(changed) +
                       " (size or SHA-256 not as in manifest.json)");
  }
  if (!missing.empty()) problems.push_back(name_list(missing) + ", listed in " + source + ", missing");
  return problems;
}

// The tile's real path when it is a file ("" for stdin or when it cannot be resolved).
std::string real_input(const std::string& input) {
  if (input.empty() || input == "-") return "";
  char real[PATH_MAX];
  return ::realpath(input.c_str(), real) != nullptr ? std::string(real) : "";
}

// Throws when the existing `t.path` may not be replaced; returns whether it exists.
bool check_existing(const Target& t, const std::string& input) {
  struct stat st {};
  if (::lstat(t.path.c_str(), &st) != 0) {
    if (errno == ENOENT) return false;
    throw DataError(t.given, "cannot look at it: " + errno_text(errno) + t.via);
  }
  if (!S_ISDIR(st.st_mode)) {
    throw DataError(t.given, "exists and is not a directory" + t.via + "; refusing to replace it");
  }
  const std::vector<std::string> problems = replace_problems(t, real_input(input));
  if (!problems.empty()) {
    std::string text;
    for (const std::string& p : problems) text += (text.empty() ? "" : "; ") + p;
    throw DataError(t.given, "refusing to replace it: not an output detect can prove it wrote" + t.via +
                                 ": " + text + ". Nothing was changed: move it away or choose another -o");
  }
  return true;
}

// ---------------------------------------------------------------------------------------
// Removing what detect wrote.

// Removes a directory detect wrote (an old output, a leftover): everything but its proof
// (manifest, index, marker) first, those last, so a run killed meanwhile leaves a directory
// the next run still recognises. Errors are ignored (what is left is a leftover).
void remove_output_tree(const fs::path& dir) {
  std::error_code ec;
  std::vector<fs::path> last;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    if (n == kManifestName || n == kIndexName || n == kPartialMarker) {
      last.push_back(it->path());
    } else {
      std::error_code e2;
      fs::remove_all(it->path(), e2);
    }
  }
  // The index, then the manifest, then the marker.
  std::sort(last.begin(), last.end(), [](const fs::path& a, const fs::path& b) {
    auto rank = [](const fs::path& p) {
      const std::string n = p.filename().string();
      return n == kIndexName ? 0 : n == kManifestName ? 1 : 2;
    };
    return rank(a) < rank(b);
  });
  for (const fs::path& p : last) fs::remove(p, ec);
  fs::remove(dir, ec);
}

// Removes the leftovers of killed runs beside the output: `.<name>.tmp<digits>` and
// `.<name>.old<digits>` directories that no live run holds locked and that hold detect's
// marker, manifest or index (or nothing). Others of that name are left, with a warning.
void remove_leftovers(const Target& t) {
  common::for_each_leftover_dir(t.parent, t.name, [](const fs::path& p) {
    std::error_code ec;
    std::string why;
    const bool empty = fs::is_empty(p, ec);
    const bool ours = empty || fs::exists(fs::symlink_status(p / kPartialMarker)) ||
                      read_manifest(p, &why).has_value() || read_legacy_index(p).has_value();
    if (ours) {
      remove_output_tree(p);
    } else {
      common::log::warn(p.string() +
                        ": left alone: named like a leftover of an interrupted detect run, but it "
                        "holds no marker, manifest or index of detect's");
    }
  });
}

// ---------------------------------------------------------------------------------------
// Writing.

// Writes files into the temporary directory and lists them for the manifest.
class DirWriter {
 public:
  explicit DirWriter(common::AtomicDir& dir) : dir_(dir) {}
  void write(const std::string& name, const std::string& bytes, bool list = true) {
    dir_.write(name, bytes);
    if (list) manifest_.files.push_back({name, bytes.size(), sha256(bytes)});
  }
  // File `name` (new) written in pieces: produce(sink) hands sink the bytes in order; each
  // piece is hashed and written as it comes (never the whole file in memory).
  void write_streamed(const std::string& name,
                      const std::function<void(const common::AtomicDir::Sink&)>& produce) {
    Sha256 digest;
    std::uint64_t size = 0;
    dir_.write_pieces(name, [&](const common::AtomicDir::Sink& sink) {
      produce([&](const char* p, std::size_t n) {
        digest.update(p, n);
        size += n;
        sink(p, n);
      });
    });
    manifest_.files.push_back({name, size, digest.finish()});
  }
  const documents::DetectManifest& manifest() const { return manifest_; }

 private:
  common::AtomicDir& dir_;
  documents::DetectManifest manifest_;
};

void step(const WriteHooks& hooks, const char* name) {
  if (hooks.step) hooks.step(name);
}

}  // namespace

documents::Candidates index_document(const Result& r, const Params& p, const std::string& tile,
                                     const std::string& classes) {
  documents::Candidates d;
  d.tile = tile;
  d.tile_points = static_cast<std::int64_t>(r.stats.points);
  d.crs = r.crs;
  d.crs_from = r.crs_from;
  d.warnings = r.warnings;
  d.origin = {r.origin.x(), r.origin.y(), r.origin.z()};
  d.classes = classes;
  d.ground = documents::GroundGrid{
      r.density.cell > 0 ? r.density.cell : p.cell,  // the cell applied (§7)
      static_cast<std::int64_t>(r.stats.cells), static_cast<std::int64_t>(r.stats.ground_cells),
      static_cast<std::int64_t>(r.stats.filled_cells), static_cast<std::int64_t>(r.stats.ground_points)};
  // The tile's measured density and what the density rule made of it (detect.md §7).
  const Density& dn = r.density;
  documents::DetectDensity density;
  density.all = dn.all;
  density.ground = dn.ground;
  density.first = dn.first;
  density.occupied_cells = static_cast<std::int64_t>(dn.occupied_cells);
  density.open_ground_cells = static_cast<std::int64_t>(dn.open_cells);
  density.rule = dn.rule;
  density.voxel = dn.voxel;
  density.voxel_by_rule = dn.voxel_by_rule;
  density.min_planarity = dn.min_planarity;
  density.planarity_by_rule = dn.planarity_by_rule;
  density.dtm_cell = dn.cell;
  density.cell_by_rule = dn.cell_by_rule;
  density.split_rows = dn.split_rows;
  density.split_rows_by_rule = dn.split_rows_by_rule;
  density.row_tolerance = dn.row_tolerance;
  d.density = documents::detect_density_json(density);
  d.margin = p.margin;
  for (const Candidate& c : r.candidates) {
    documents::Candidate e;
    e.id = c.id;
    e.file = c.id + ".pcd";
    for (int row = 0; row < 4; ++row) {
      for (int col = 0; col < 4; ++col) e.transform[4 * row + col] = c.to_tile(row, col);
    }
    e.centre = std::array<double, 3>{c.to_tile(0, 3), c.to_tile(1, 3), c.to_tile(2, 3)};
    e.length = c.length;
    e.width = c.width;
    e.heading = c.heading;
    e.height = c.height;
    e.point_count = static_cast<std::int64_t>(c.cloud.size());
    e.object_points = static_cast<std::int64_t>(c.object_points);
    e.density = c.density;
    e.planarity = c.planarity;
    e.planar_area = c.planar_area;
    d.candidates.push_back(std::move(e));
  }
  return d;
}

std::string serialize_index(const Result& r, const Params& p, const formats::Provenance& prov,
                            const std::string& tile, const std::string& classes) {
  return documents::write_candidates(index_document(r, p, tile, classes), prov);
}

void check_output_dir(const std::string& dir, const std::string& input) {
  check_existing(resolve_target(dir), input);
}

void write_output(const std::string& dir, const formats::PointCloud& tile, const Result& result,
                  const Params& params, const formats::Provenance& provenance, const std::string& tile_name,
                  bool write_classes, const WriteHooks& hooks) {
  const Target t = resolve_target(dir);
  check_existing(t, tile_name);
  remove_leftovers(t);
  common::AtomicDir temp(t.parent, t.name, t.given, t.via, {hooks.step, hooks.no_exchange});
  DirWriter out(temp);
  out.write(kPartialMarker, "", false);
  step(hooks, "created");
  // Every file's comments: the tile's own (a candidate's crop keeps them), detect's
  // provenance, then what the file holds.
  const std::vector<std::string> prov = formats::provenance_comments(provenance);
  for (const Candidate& c : result.candidates) {
    const std::string name = c.id + ".pcd";
    out.write(name, candidate_pcd(c, prov, (temp.temp() / name).string()));
  }
  std::string classes;
  if (write_classes) {
    classes = "classes.ply";
    // In pieces: the file (20 bytes a point) is never held whole (cost.md §17).
    out.write_streamed(classes, [&](const std::function<void(const char*, std::size_t)>& sink) {
      classes_ply(tile, result, prov, sink);
    });
  }
  out.write(kIndexName, serialize_index(result, params, provenance, tile_name, classes));
  out.write(kManifestName, documents::write_detect_manifest(out.manifest()), false);
  temp.remove(kPartialMarker);
  step(hooks, "written");
  // Again, just before the swap: the directory may have changed during the work.
  temp.publish([&] { return check_existing(t, tile_name); },
               [](const fs::path& old) { remove_output_tree(old); });
}

}  // namespace canopy::detect
