#include "canopy/formats/point_cloud.h"

#include <algorithm>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <variant>

#include "canopy/common/error.h"

namespace canopy::formats {
namespace {

// The double a packed raw value stands for: the readers' own expressions.
template <typename T>
inline double unpack_one(T raw, bool scaled, double scale, double shift) {
  return scaled ? static_cast<double>(raw) * scale + shift : static_cast<double>(raw);
}

std::size_t packed_size(const PackedValues& p) {
  return std::visit(
      [](const auto& v) -> std::size_t {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>) {
          return 0;
        } else {
          return v.size();
        }
      },
      p);
}

}  // namespace

PointCloud::Column::Column(const Column& o)
    : values(o.values),
      packed(o.packed),
      scaled(o.scaled),
      scale(o.scale),
      shift(o.shift),
      is_packed(o.is_packed.load(std::memory_order_acquire)) {}

PointCloud::Column& PointCloud::Column::operator=(const Column& o) {
  values = o.values;
  packed = o.packed;
  scaled = o.scaled;
  scale = o.scale;
  shift = o.shift;
  is_packed.store(o.is_packed.load(std::memory_order_acquire), std::memory_order_release);
  return *this;
}

PointCloud::PointCloud(const PointCloud& o) : comments(o.comments) {
  const std::lock_guard<std::mutex> lock(o.unpack_);  // no column of o changes meanwhile
  size_ = o.size_;
  names_ = o.names_;
  types_ = o.types_;
  data_ = o.data_;
}

PointCloud::PointCloud(PointCloud&& o) noexcept
    : comments(std::move(o.comments)),
      size_(o.size_),
      names_(std::move(o.names_)),
      types_(std::move(o.types_)),
      data_(std::move(o.data_)) {
  o.size_ = 0;
}

PointCloud& PointCloud::operator=(const PointCloud& o) {
  if (this != &o) *this = PointCloud(o);
  return *this;
}

PointCloud& PointCloud::operator=(PointCloud&& o) noexcept {
  if (this != &o) {
    comments = std::move(o.comments);
    size_ = o.size_;
    names_ = std::move(o.names_);
    types_ = std::move(o.types_);
    data_ = std::move(o.data_);
    o.size_ = 0;
    o.names_.clear();
    o.types_.clear();
    o.data_.clear();
  }
  return *this;
}

std::vector<double>& PointCloud::unpacked(std::size_t i) const {
  Column& c = data_.at(i);
  if (!c.is_packed.load(std::memory_order_acquire)) return c.values;
  const std::lock_guard<std::mutex> lock(unpack_);
  if (c.is_packed.load(std::memory_order_relaxed)) {
    std::visit(
        [&c](auto& v) {
          using V = std::decay_t<decltype(v)>;
          if constexpr (std::is_same_v<V, std::vector<double>>) {
            if (!c.scaled) {  // already the doubles: moved, not copied (cost.md §17)
              c.values = std::move(v);
              return;
            }
          }
          if constexpr (!std::is_same_v<V, std::monostate>) {
            std::vector<double> out;
            out.reserve(v.size());
            if (c.scaled) {
              for (const auto raw : v) out.push_back(unpack_one(raw, true, c.scale, c.shift));
            } else {
              out.assign(v.begin(), v.end());  // static_cast<double>, as unpack_one
            }
            c.values = std::move(out);
          }
        },
        c.packed);
    c.packed = std::monostate{};
    c.is_packed.store(false, std::memory_order_release);
  }
  return c.values;
}

bool PointCloud::packed(std::size_t i) const { return data_.at(i).is_packed.load(std::memory_order_acquire); }

double PointCloud::value(std::size_t i, std::size_t row) const {
  const Column& c = data_.at(i);
  if (!c.is_packed.load(std::memory_order_acquire)) return c.values.at(row);
  const std::lock_guard<std::mutex> lock(unpack_);  // another thread may be unpacking it
  if (!c.is_packed.load(std::memory_order_relaxed)) return c.values.at(row);
  return std::visit(
      [&c, row](const auto& v) -> double {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>) {
          return 0.0;
        } else {
          return unpack_one(v.at(row), c.scaled, c.scale, c.shift);
        }
      },
      c.packed);
}

void PointCloud::values(std::size_t i, std::size_t first, std::size_t count, double* out) const {
  const Column& c = data_.at(i);
  if (count == 0) return;
  auto check = [&](std::size_t have) {
    if (first > have || count > have - first) throw std::out_of_range("rows beyond the column");
  };
  if (!c.is_packed.load(std::memory_order_acquire)) {
    check(c.values.size());
    std::copy(c.values.begin() + static_cast<std::ptrdiff_t>(first),
              c.values.begin() + static_cast<std::ptrdiff_t>(first + count), out);
    return;
  }
  const std::lock_guard<std::mutex> lock(unpack_);
  if (!c.is_packed.load(std::memory_order_relaxed)) {
    check(c.values.size());
    std::copy(c.values.begin() + static_cast<std::ptrdiff_t>(first),
              c.values.begin() + static_cast<std::ptrdiff_t>(first + count), out);
    return;
  }
  std::visit(
      [&](const auto& v) {
        if constexpr (!std::is_same_v<std::decay_t<decltype(v)>, std::monostate>) {
          check(v.size());
          for (std::size_t r = 0; r < count; ++r)
            out[r] = unpack_one(v[first + r], c.scaled, c.scale, c.shift);
        }
      },
      c.packed);
}

void PointCloud::resize(std::size_t n) {
  size_ = n;
  for (std::size_t i = 0; i < data_.size(); ++i) {
    Column& c = data_[i];
    if (c.is_packed.load(std::memory_order_acquire) && packed_size(c.packed) == n) continue;
    unpacked(i).resize(n, 0.0);
  }
}

std::size_t PointCloud::index(const std::string& name) const {
  for (std::size_t i = 0; i < names_.size(); ++i) {
    if (names_[i] == name) return i;
  }
  return names_.size();
}

bool PointCloud::has(const std::string& name) const { return index(name) < names_.size(); }

std::vector<double>& PointCloud::add(const std::string& name, FieldType type) {
  const std::size_t i = index(name);
  if (i < names_.size()) {
    types_[i] = type;
    return unpacked(i);
  }
  names_.push_back(name);
  types_.push_back(type);
  data_.emplace_back();
  data_.back().values.assign(size_, 0.0);
  return data_.back().values;
}

std::vector<double>& PointCloud::col(const std::string& name) {
  const std::size_t i = index(name);
  if (i == names_.size()) throw std::out_of_range("field '" + name + "' missing");
  return unpacked(i);
}

const std::vector<double>& PointCloud::col(const std::string& name) const {
  const std::size_t i = index(name);
  if (i == names_.size()) throw std::out_of_range("field '" + name + "' missing");
  return unpacked(i);
}

FieldType PointCloud::type(const std::string& name) const {
  const std::size_t i = index(name);
  if (i == names_.size()) throw std::out_of_range("field '" + name + "' missing");
  return types_[i];
}

void PointCloud::remove(const std::string& name) {
  const std::size_t i = index(name);
  if (i == names_.size()) return;
  names_.erase(names_.begin() + static_cast<std::ptrdiff_t>(i));
  types_.erase(types_.begin() + static_cast<std::ptrdiff_t>(i));
  data_.erase(data_.begin() + static_cast<std::ptrdiff_t>(i));
}

void PointCloud::require(const std::vector<std::string>& names, const std::string& file,
                         const std::string& hint) const {
  for (const auto& n : names) {
    if (!has(n)) {
      throw common::DataError(
          file, "field '" + n + "' missing" + (hint.empty() ? std::string() : " (" + hint + ")"));
    }
  }
}

PointCloud PointCloud::select(const std::vector<std::size_t>& keep) const {
  PointCloud out;
  out.comments = comments;
  out.names_ = names_;
  out.types_ = types_;
  out.size_ = keep.size();
  out.data_.resize(data_.size());
  const std::lock_guard<std::mutex> lock(unpack_);  // no column changes meanwhile
  for (std::size_t c = 0; c < data_.size(); ++c) {
    const Column& src = data_[c];
    Column& dst = out.data_[c];
    if (!src.is_packed.load(std::memory_order_relaxed)) {
      dst.values.resize(keep.size());
      for (std::size_t r = 0; r < keep.size(); ++r) dst.values[r] = src.values.at(keep[r]);
      continue;
    }
    // A packed column stays packed: the same raw values, the same scale.
    dst.scaled = src.scaled;
    dst.scale = src.scale;
    dst.shift = src.shift;
    std::visit(
        [&](const auto& v) {
          using V = std::decay_t<decltype(v)>;
          if constexpr (!std::is_same_v<V, std::monostate>) {
            V& d = dst.packed.template emplace<V>();
            d.reserve(keep.size());
            for (std::size_t r : keep) d.push_back(v.at(r));
          }
        },
        src.packed);
    dst.is_packed.store(true, std::memory_order_relaxed);
  }
  return out;
}

}  // namespace canopy::formats
