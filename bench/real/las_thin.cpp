// Thins a LAS/LAZ tile by pulses (docs/decisions/real-tiles.md, "Recall against density on the
// real development tiles, by thinning", stop 71): keeps a seeded fraction of the laser pulses,
// every return of a kept pulse, and writes uncompressed LAS in the file's own version and point
// format (the header, VLRs, point records and EVLRs byte for byte as read; the counts, the
// counts by return and the bounding box of the kept points set anew). A bench program, not a
// tool.
//
//   las_thin -i IN.las|IN.laz -o OUT.las --fraction F [--seed S] [--per-point] [--systematic]
//
// A pulse is the points sharing gps_time, point_source_id and (formats 6-10) scanner_channel;
// a file without gps_time, or whose gps_time is 0 everywhere, and --per-point, thin point by
// point. Each pulse gets a rank from a seeded 64-bit mix of its key (common::mix64); the
// round(F x pulses) pulses of lowest rank are kept, so a run is deterministic for a seed, keeps
// F of the pulses exactly (to one pulse), and a smaller F keeps a subset of a larger F's pulses
// (the same seed): the ladder's rungs are nested. --systematic instead keeps evenly spaced pulses
// in time order (every 1/F-th, the seed setting the phase): a lower pulse rate's regular pattern
// rather than random holes (not nested across F). Prints one line on stderr: points and pulses
// read and kept, returns per pulse, and how many pulses hold more points than their
// number_of_returns says (a key shared by two pulses).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/rng.h"
#include "canopy/formats/las.h"
#include "canopy/formats/laz.h"

using namespace canopy;

namespace {

template <typename T>
T get(const std::string& b, std::size_t at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof v);
  return v;
}
template <typename T>
void set(std::string* b, std::size_t at, T v) {
  std::memcpy(&(*b)[at], &v, sizeof v);
}

std::uint64_t bits(double d) {
  std::uint64_t u;
  std::memcpy(&u, &d, sizeof u);
  return u;
}

struct Pulse {
  std::uint64_t rank, key;
  std::size_t first, count;  // its points: order[first .. first + count - 1]
};
struct Pulses {
  std::vector<std::size_t> order;  // the points, pulse by pulse
  std::vector<Pulse> pulses;
  std::size_t shared = 0;  // pulses with more points than their number_of_returns
};

// The points grouped into pulses: by gps_time, point_source_id and scanner_channel, or (by_gps
// false) one pulse per point; each pulse ranked by the seeded mix of its key.
Pulses group(const formats::PointCloud& cloud, bool by_gps, std::uint64_t seed) {
  const std::size_t n = cloud.size();
  std::vector<std::uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!by_gps) {
      key[i] = common::mix64(i);
      continue;
    }
    std::uint64_t k = common::mix64(bits(cloud.col("gps_time")[i]));
    if (cloud.has("point_source_id"))
      k = common::mix64(k ^ static_cast<std::uint64_t>(cloud.col("point_source_id")[i]));
    if (cloud.has("scanner_channel"))
      k = common::mix64(k ^ (static_cast<std::uint64_t>(cloud.col("scanner_channel")[i]) << 20));
    key[i] = k;
  }
  Pulses r;
  r.order.resize(n);
  for (std::size_t i = 0; i < n; ++i) r.order[i] = i;
  std::stable_sort(r.order.begin(), r.order.end(),
                   [&](std::size_t p, std::size_t q) { return key[p] < key[q]; });
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t i = r.order[j];
    if (r.pulses.empty() || key[i] != r.pulses.back().key)
      r.pulses.push_back({common::mix64(key[i] ^ common::mix64(seed)), key[i], j, 0});
    ++r.pulses.back().count;
  }
  if (by_gps && cloud.has("number_of_returns")) {
    const std::vector<double>& nr = cloud.col("number_of_returns");
    for (const auto& p : r.pulses) {
      double most = 0;
      for (std::size_t j = p.first; j < p.first + p.count; ++j) most = std::max(most, nr[r.order[j]]);
      r.shared += static_cast<double>(p.count) > std::max(most, 1.0);
    }
  }
  return r;
}

struct Args {
  std::string in, out;
  double fraction = -1;
  std::uint64_t seed = 1;
  bool per_point = false;
  bool systematic = false;
};

Args parse(int argc, char** argv) {
  Args a;
  auto value = [&](int* i) {
    if (*i + 1 >= argc) throw common::UsageError(std::string(argv[*i]) + " needs a value");
    return std::string(argv[++*i]);
  };
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (k == "-i") {
      a.in = value(&i);
    } else if (k == "-o") {
      a.out = value(&i);
    } else if (k == "--fraction") {
      const std::string v = value(&i);
      char* end = nullptr;
      a.fraction = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !(a.fraction >= 0 && a.fraction <= 1))
        throw common::UsageError("--fraction " + v + ": a number from 0 to 1");
    } else if (k == "--seed") {
      const std::string v = value(&i);
      char* end = nullptr;
      a.seed = std::strtoull(v.c_str(), &end, 10);
      if (end == v.c_str() || *end != '\0' || v[0] == '-')
        throw common::UsageError("--seed " + v + ": a whole number");
    } else if (k == "--per-point") {
      a.per_point = true;
    } else if (k == "--systematic") {
      a.systematic = true;
    } else {
      throw common::UsageError("unknown argument " + k);
    }
  }
  if (a.in.empty() || a.out.empty() || a.fraction < 0)
    throw common::UsageError(
        "usage: las_thin -i IN.las|IN.laz -o OUT.las --fraction F [--seed S] [--per-point] [--systematic]");
  return a;
}

int run(const Args& a) {
  const std::string name = common::display_name(a.in);
  std::string las = common::read_file(a.in);
  if (!formats::is_las(las)) throw common::DataError(name, "not a LAS or LAZ file");
  if (formats::laszip_compressed(las)) las = formats::laz_to_las(las, name);
  const formats::PointCloud cloud = formats::parse_las(
      las, name,
      formats::FieldSelection::only({"x", "y", "z", "gps_time", "point_source_id", "scanner_channel",
                                     "return_number", "number_of_returns"}));
  // The header block (the reader has checked it): LAS 1.0-1.4.
  const int minor = static_cast<unsigned char>(las[25]);
  const auto offset = get<std::uint32_t>(las, 96);
  const int format = static_cast<unsigned char>(las[104]) & 0x3f;
  const auto record = get<std::uint16_t>(las, 105);
  const std::uint32_t legacy = get<std::uint32_t>(las, 107);
  const std::uint64_t n = cloud.size();
  if (format == 4 || format == 5 || format >= 9)
    throw common::DataError(name, "point format " + std::to_string(format) + " (waveform) is not thinned");
  const std::size_t end = offset + n * record;
  if (end > las.size()) throw common::DataError(name, "point records past the end of the file");

  // Pulses: by gps_time (and source, channel) unless that does not separate them.
  bool has_gps =
      !a.per_point && cloud.has("gps_time") &&
      std::any_of(cloud.col("gps_time").begin(), cloud.col("gps_time").end(), [](double t) { return t != 0; });
  std::string note;
  Pulses ps = group(cloud, has_gps, a.seed);
  if (has_gps && ps.shared * 100 > ps.pulses.size()) {
    // gps_time stored too coarsely to tell the pulses apart (forest_chablais3: 0.0144 s steps,
    // 25 points a "pulse"): point by point instead.
    note = "gps_time does not separate the pulses (" + std::to_string(ps.shared) + " of " +
           std::to_string(ps.pulses.size()) +
           " hold more points than their number_of_returns): thinned per point";
    has_gps = false;
    ps = group(cloud, false, a.seed);
  }
  const std::vector<Pulse>& pulses = ps.pulses;
  const std::vector<std::size_t>& order = ps.order;
  const std::size_t shared = ps.shared;
  std::vector<std::size_t> by_rank(pulses.size());
  for (std::size_t k = 0; k < pulses.size(); ++k) by_rank[k] = k;
  std::size_t keep_pulses = 0;
  std::vector<char> keep(n, 0);
  if (!a.systematic) {
    std::sort(by_rank.begin(), by_rank.end(), [&](std::size_t p, std::size_t q) {
      return pulses[p].rank != pulses[q].rank ? pulses[p].rank < pulses[q].rank : pulses[p].key < pulses[q].key;
    });
    keep_pulses = static_cast<std::size_t>(std::llround(a.fraction * static_cast<double>(pulses.size())));
  } else {
    // In time order (a pulse's gps_time; per point, the file's order), every pulse j with
    // floor((j + 1) F + phase) > floor(j F + phase): evenly spaced along the scan, the seed
    // giving the phase. by_rank then lists the kept pulses first.
    auto when = [&](const Pulse& p) {
      const std::size_t i = order[p.first];
      return has_gps ? cloud.col("gps_time")[i] : static_cast<double>(i);
    };
    std::sort(by_rank.begin(), by_rank.end(), [&](std::size_t p, std::size_t q) {
      const double tp = when(pulses[p]), tq = when(pulses[q]);
      return tp != tq ? tp < tq : pulses[p].key < pulses[q].key;
    });
    const double phase = static_cast<double>(common::mix64(a.seed) >> 11) * 0x1.0p-53;
    std::vector<std::size_t> kept_first;
    for (std::size_t j = 0; j < by_rank.size(); ++j) {
      const double jd = static_cast<double>(j);
      if (std::floor((jd + 1) * a.fraction + phase) > std::floor(jd * a.fraction + phase))
        kept_first.push_back(by_rank[j]);
    }
    keep_pulses = kept_first.size();
    std::copy(kept_first.begin(), kept_first.end(), by_rank.begin());
  }
  for (std::size_t k = 0; k < keep_pulses; ++k) {
    const Pulse& p = pulses[by_rank[k]];
    for (std::size_t j = p.first; j < p.first + p.count; ++j) keep[order[j]] = 1;
  }

  // The output: the header block as read, the kept records in file order, what followed them.
  std::string out = las.substr(0, offset);
  std::uint64_t kept = 0, by_return[15] = {};
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  const std::vector<double>* xyz[3] = {&cloud.col("x"), &cloud.col("y"), &cloud.col("z")};
  const std::vector<double>* ret = cloud.has("return_number") ? &cloud.col("return_number") : nullptr;
  out.reserve(offset + n * record + (las.size() - end));
  for (std::size_t i = 0; i < n; ++i) {
    if (!keep[i]) continue;
    out.append(las, offset + i * record, record);
    for (int d = 0; d < 3; ++d) {
      const double v = (*xyz[d])[i];
      if (kept == 0 || v < lo[d]) lo[d] = v;
      if (kept == 0 || v > hi[d]) hi[d] = v;
    }
    const int r = ret ? static_cast<int>((*ret)[i]) : 0;
    if (r >= 1 && r <= 15) ++by_return[r - 1];
    ++kept;
  }
  out.append(las, end, std::string::npos);
  if (legacy != 0 || format < 6) {
    if (kept > 0xffffffffu) throw common::DataError(name, "too many points for LAS's 32-bit count");
    set<std::uint32_t>(&out, 107, static_cast<std::uint32_t>(kept));
    for (int k = 0; k < 5; ++k)
      set<std::uint32_t>(&out, 111 + 4 * k, static_cast<std::uint32_t>(by_return[k]));
  }
  for (int d = 0; d < 3; ++d) {
    set<double>(&out, 179 + 16 * d, hi[d]);
    set<double>(&out, 187 + 16 * d, lo[d]);
  }
  if (minor >= 3 && get<std::uint64_t>(las, 227) != 0)
    throw common::DataError(name, "waveform data in the file: not thinned");
  if (minor >= 4) {
    const auto evlr = get<std::uint64_t>(las, 235);
    if (evlr != 0) set<std::uint64_t>(&out, 235, evlr - (n - kept) * record);
    set<std::uint64_t>(&out, 247, kept);
    for (int k = 0; k < 15; ++k) set<std::uint64_t>(&out, 255 + 8 * k, by_return[k]);
  }
  common::write_file_atomic(a.out, std::move(out));
  std::fprintf(
      stderr,
      "las_thin: %s: %llu points, %zu %s (%.3f points each; %zu with more points than their "
      "number_of_returns); kept %zu (%.4f) with %llu points (%.4f), seed %llu\n",
      name.c_str(), static_cast<unsigned long long>(n), pulses.size(),
      has_gps ? "pulses" : "points (no pulses)",
      pulses.empty() ? 0.0 : static_cast<double>(n) / static_cast<double>(pulses.size()), shared, keep_pulses,
      pulses.empty() ? 0.0 : static_cast<double>(keep_pulses) / static_cast<double>(pulses.size()),
      static_cast<unsigned long long>(kept), n ? static_cast<double>(kept) / static_cast<double>(n) : 0.0,
      static_cast<unsigned long long>(a.seed));
  if (!note.empty()) std::fprintf(stderr, "las_thin: %s: %s\n", name.c_str(), note.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const common::Error& e) {
    std::fprintf(stderr, "las_thin: error: %s\n", e.what());
    return e.exit_code();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "las_thin: error: %s\n", e.what());
    return 1;
  }
}
