#include "baseline/model_cache.h"

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"

// The body is the floats' and counts' own bytes (little-endian IEEE 754, formats/README.md).
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "canopy.baseline-models is little-endian");

namespace canopy::baseline {
namespace {

using common::DataError;

constexpr const char* kFormat = "canopy.baseline-models";
constexpr int kVersion = 1;
constexpr std::size_t kMaxLine = 4096;
const char* const kRemedy =
    " (make it again: baseline --prepare --modelbase DIR -o FILE with this run's parameters; "
    "the experiment's make does so when the modelbase or baseline.ini changes)";

std::uint64_t fnv1a(const char* data, std::size_t n) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::string hex(std::uint64_t v) {
  char s[17];
  std::snprintf(s, sizeof s, "%016" PRIx64, v);
  return s;
}

std::string exact(double v) {
  char s[40];
  std::snprintf(s, sizeof s, "%.17g", v);
  return s;
}

// The parameters the models' side depends on, as (header key, value).
std::vector<std::pair<std::string, double>> side_parameters(const Params& p) {
  return {{"voxel", p.voxel},
          {"normal_radius", p.normal_radius},
          {"feature_radius", p.feature_radius},
          {"views", static_cast<double>(p.views)},
          {"view_elevation", p.view_elevation}};
}

template <typename T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// Reads the file's header lines and body, each step checked against the bytes left.
class Reader {
 public:
  Reader(const std::string& bytes, const std::string& path) : bytes_(bytes), path_(path) {}

  std::string line(const std::string& what) {
    const std::size_t end = bytes_.find('\n', pos_);
    if (end == std::string::npos || end - pos_ > kMaxLine)
      fail("truncated or corrupt header (at " + what + ")");
    std::string s = bytes_.substr(pos_, end - pos_);
    pos_ = end + 1;
    return s;
  }

  // A header line "<key> <value...>": the value, after checking the key.
  std::string field(const std::string& key) {
    const std::string s = line(key);
    if (s.compare(0, key.size() + 1, key + " ") != 0)
      fail("corrupt header: expected '" + key + " ...', found '" + s + "'");
    return s.substr(key.size() + 1);
  }

  template <typename T>
  T take(const char* what) {
    T v;
    if (bytes_.size() - pos_ < sizeof v) fail(std::string("corrupt body: ends inside ") + what);
    std::memcpy(&v, bytes_.data() + pos_, sizeof v);
    pos_ += sizeof v;
    return v;
  }

  template <typename Array>
  void take_floats(Array& a) {
    const std::size_t n = sizeof(float) * a.size();
    if (bytes_.size() - pos_ < n) fail("corrupt body: ends inside a model's floats");
    std::memcpy(a.data(), bytes_.data() + pos_, n);
    pos_ += n;
  }

  // A count of `each`-byte records that the bytes left can hold.
  std::uint32_t count(std::size_t each, const char* what) {
    const auto n = take<std::uint32_t>(what);
    if (static_cast<std::uint64_t>(n) * each > bytes_.size() - pos_) {
      fail(std::string("corrupt body: ") + what + " " + std::to_string(n) + " exceeds the file");
    }
    return n;
  }

  std::size_t pos() const { return pos_; }
  std::size_t left() const { return bytes_.size() - pos_; }
  const char* here() const { return bytes_.data() + pos_; }
  [[noreturn]] void fail(const std::string& cause) const { throw DataError(path_, cause); }

 private:
  const std::string& bytes_;
  const std::string& path_;
  std::size_t pos_ = 0;
};

std::uint64_t parse_u64(Reader& r, const std::string& text, int base, const std::string& what) {
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), &end, base);
  if (text.empty() || text[0] == '-' || *end != '\0' || errno != 0)
    r.fail("corrupt header: " + what + " '" + text + "'");
  return v;
}

}  // namespace

std::vector<SurfaceStamp> stamp_modelbase(const std::string& dir) {
  std::vector<SurfaceStamp> out;
  for (const auto& [name, path] : list_modelbase(dir)) {
    const std::string bytes = common::read_file(path);
    out.push_back({name, bytes.size(), fnv1a(bytes.data(), bytes.size())});
  }
  return out;
}

std::string serialize_prepared(const PreparedModels& models, const Params& params,
                               const std::vector<SurfaceStamp>& stamps) {
  if (!models.vfh || !models.fpfh || models.models.size() != stamps.size()) {
    throw std::logic_error("serialize_prepared: both methods' sides of every stamped model");
  }
  std::string body;
  for (const auto& m : models.models) {
    put(body, static_cast<std::uint32_t>(m.vfh.size()));
    for (std::size_t v = 0; v < m.vfh.size(); ++v) {
      put(body, m.seen[v]);
      body.append(reinterpret_cast<const char*>(m.vfh[v].data()), sizeof(float) * m.vfh[v].size());
    }
    put(body, static_cast<std::uint32_t>(m.points.size()));
    for (const auto& a : m.points)
      body.append(reinterpret_cast<const char*>(a.data()), sizeof(float) * a.size());
    put(body, static_cast<std::uint8_t>(m.features_dense ? 1 : 0));
    put(body, static_cast<std::uint32_t>(m.features.size()));
    for (const auto& a : m.features)
      body.append(reinterpret_cast<const char*>(a.data()), sizeof(float) * a.size());
  }
  std::ostringstream h;
  h << kFormat << ' ' << kVersion << '\n' << "tool baseline " << CANOPY_VERSION << '\n';
  for (const auto& [key, value] : side_parameters(params)) h << key << ' ' << exact(value) << '\n';
  h << "models " << stamps.size() << '\n';
  for (std::size_t i = 0; i < stamps.size(); ++i) {
    const SurfaceStamp& s = stamps[i];
    if (s.name != models.models[i].name)
      throw std::logic_error("serialize_prepared: models and stamps differ");
    if (s.name.empty() || s.name.find('\n') != std::string::npos || s.name.size() > 1024) {
      throw DataError(s.name + ".pcd",
                      "a model name the file cannot record (empty, a line break, > 1024 bytes)");
    }
    h << "model " << s.bytes << ' ' << hex(s.fnv1a) << ' ' << s.name << '\n';
  }
  h << "body " << body.size() << ' ' << hex(fnv1a(body.data(), body.size())) << '\n';
  return h.str() + body;
}

PreparedModels parse_prepared(const std::string& bytes, const std::string& path, const Params& params,
                              const std::vector<SurfaceStamp>& stamps) {
  Reader r(bytes, path);
  const std::string magic = std::string(kFormat) + " ";
  if (bytes.compare(0, magic.size(), magic) != 0) {
    r.fail(std::string("not a ") + kFormat + " file (baseline --prepare writes one)");
  }
  const std::string version = r.field(kFormat);
  if (version != std::to_string(kVersion)) {
    r.fail(std::string(kFormat) + " version '" + version + "' unknown (this baseline reads " +
           std::to_string(kVersion) + ")");
  }
  r.field("tool");  // provenance only: the make graph remakes the file when the tool changes
  for (const auto& [key, value] : side_parameters(params)) {
    const std::string text = r.field(key);
    char* end = nullptr;
    const double recorded = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0') r.fail("corrupt header: " + key + " '" + text + "'");
    if (recorded != value) {
      r.fail("prepared with " + key + " " + exact(recorded) + ", this run has " + exact(value) + kRemedy);
    }
  }
  const std::uint64_t n = parse_u64(r, r.field("models"), 10, "model count");
  if (n != stamps.size()) {
    r.fail("prepared from another modelbase: " + std::to_string(n) + " models, the modelbase has " +
           std::to_string(stamps.size()) + kRemedy);
  }
  for (const SurfaceStamp& s : stamps) {
    const std::string text = r.field("model");
    std::istringstream in(text);
    std::string size, hash;
    in >> size >> hash;
    const std::string name = in.get() == ' ' ? text.substr(static_cast<std::size_t>(in.tellg())) : "";
    if (name.empty()) r.fail("corrupt header: model line '" + text + "'");
    if (name != s.name) {
      r.fail("prepared from another modelbase: it has model '" + name + "' where the modelbase has '" +
             s.name + "'" + kRemedy);
    }
    if (parse_u64(r, size, 10, "size") != s.bytes || parse_u64(r, hash, 16, "hash") != s.fnv1a) {
      r.fail("prepared from another modelbase: " + s.name + ".pcd changed since (size or FNV-1a differs)" +
             kRemedy);
    }
  }
  std::istringstream body_line(r.field("body"));
  std::string size, hash;
  body_line >> size >> hash;
  const std::uint64_t body_bytes = parse_u64(r, size, 10, "body size");
  if (body_bytes != r.left()) {
    r.fail("truncated or corrupt: the body has " + std::to_string(r.left()) + " bytes, the header says " +
           std::to_string(body_bytes));
  }
  if (parse_u64(r, hash, 16, "body hash") != fnv1a(r.here(), r.left())) {
    r.fail("corrupt: the body's FNV-1a differs from the header's");
  }
  PreparedModels out;
  out.vfh = out.fpfh = true;
  const std::size_t views = static_cast<std::size_t>(params.views) + 1;
  for (const SurfaceStamp& s : stamps) {
    PreparedModel m;
    m.name = s.name;
    if (r.take<std::uint32_t>("a view count") != views) r.fail("corrupt body: " + s.name + ": view count");
    m.seen.resize(views);
    m.vfh.resize(views);
    for (std::size_t v = 0; v < views; ++v) {
      m.seen[v] = r.take<std::uint8_t>("a view flag");
      r.take_floats(m.vfh[v]);
    }
    m.points.resize(r.count(sizeof(float) * 9, "point count"));
    for (auto& a : m.points) r.take_floats(a);
    const auto dense = r.take<std::uint8_t>("a flag");
    if (dense > 1) r.fail("corrupt body: " + s.name + ": flag " + std::to_string(dense));
    m.features_dense = dense == 1;
    m.features.resize(r.count(sizeof(float) * 33, "feature count"));
    if (!m.features.empty() && m.features.size() != m.points.size()) {
      r.fail("corrupt body: " + s.name + ": " + std::to_string(m.features.size()) + " features for " +
             std::to_string(m.points.size()) + " points");
    }
    for (auto& a : m.features) r.take_floats(a);
    out.models.push_back(std::move(m));
  }
  if (r.left() != 0) r.fail("corrupt body: " + std::to_string(r.left()) + " bytes after the last model");
  return out;
}

std::string prepare_file(const std::string& modelbase, const Params& params, std::size_t* model_count) {
  const auto before = stamp_modelbase(modelbase);
  const auto models = read_modelbase(modelbase);
  const auto after = stamp_modelbase(modelbase);
  bool same = before.size() == after.size();
  for (std::size_t i = 0; same && i < before.size(); ++i) {
    same = before[i].name == after[i].name && before[i].bytes == after[i].bytes &&
           before[i].fnv1a == after[i].fnv1a;
  }
  if (!same)
    throw DataError(modelbase, "the modelbase changed while it was read (run again when it is complete)");
  if (model_count != nullptr) *model_count = models.size();
  return serialize_prepared(prepare_models(models, params, true, true), params, after);
}

PreparedModels load_prepared(const std::string& path, const std::string& modelbase, const Params& params) {
  const std::string bytes = common::read_file(path);
  return parse_prepared(bytes, path, params, stamp_modelbase(modelbase));
}

}  // namespace canopy::baseline
