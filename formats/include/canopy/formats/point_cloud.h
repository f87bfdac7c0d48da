// In-memory point set with any set of named scalar fields (column-major, one
// std::vector<double> per field: every PCD/PLY scalar type up to 32 bits is exact in a double).
// Shared by PCD clouds and PLY mesh vertices.
//
// A reader may store a column packed, at its width in the file (PackedValues: uint8 ... double,
// optionally scaled: value = raw * scale + shift, as LAS stores x y z). A packed column is turned
// into its std::vector<double> on the first col() that asks for it (then the packed values are
// freed), so every caller sees doubles, bit for bit those the reader would have stored; size(),
// names(), types(), select(), value() and copies keep it packed. col() on a const cloud may thus
// change the storage: it is safe from several threads at once (one lock per unpacking).
// docs/decisions/cost.md section 7.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace canopy::formats {

// Storage type of a field on disk: PCD's TYPE/SIZE pair ('F',4) = float32, ('F',8) = float64,
// ('U',1) = uint8, ('U',2), ('U',4), ('I',1), ('I',2), ('I',4).
struct FieldType {
  char kind = 'F';
  int size = 4;
  bool operator==(const FieldType& o) const { return kind == o.kind && size == o.size; }
};

inline constexpr FieldType kFloat32{'F', 4};
inline constexpr FieldType kFloat64{'F', 8};
inline constexpr FieldType kUint8{'U', 1};
inline constexpr FieldType kUint32{'U', 4};
inline constexpr FieldType kInt32{'I', 4};

// A column's values at their stored width (std::monostate: not packed).
using PackedValues =
    std::variant<std::monostate, std::vector<std::uint8_t>, std::vector<std::int8_t>, std::vector<std::uint16_t>,
                 std::vector<std::int16_t>, std::vector<std::uint32_t>, std::vector<std::int32_t>,
                 std::vector<std::uint64_t>, std::vector<std::int64_t>, std::vector<float>, std::vector<double>>;

// The fields a reader keeps: every field (the default) or only the named ones the file has
// (a name the file lacks is no error here: the caller's require() words that).
class FieldSelection {
 public:
  FieldSelection() = default;  // every field
  static FieldSelection only(std::vector<std::string> names) {
    FieldSelection s;
    s.all_ = false;
    s.names_ = std::move(names);
    return s;
  }
  bool all() const { return all_; }
  bool wants(const std::string& name) const {
    if (all_) return true;
    for (const auto& n : names_) {
      if (n == name) return true;
    }
    return false;
  }

 private:
  bool all_ = true;
  std::vector<std::string> names_;
};

class PointCloud {
 public:
  PointCloud() = default;
  PointCloud(const PointCloud& o);
  PointCloud(PointCloud&& o) noexcept;
  PointCloud& operator=(const PointCloud& o);
  PointCloud& operator=(PointCloud&& o) noexcept;
  ~PointCloud() = default;

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  // Resizes every column (new entries are 0). A packed column of another length is unpacked
  // first.
  void resize(std::size_t n);

  bool has(const std::string& name) const;
  // Adds a zero-filled column, or returns the existing one (its type is then changed to `type`).
  // References to columns stay valid while further columns are added.
  std::vector<double>& add(const std::string& name, FieldType type = kFloat32);
  // Column access; throws std::out_of_range naming the field when missing (readers and tools
  // turn that into a DataError naming the file, see require()).
  std::vector<double>& col(const std::string& name);
  const std::vector<double>& col(const std::string& name) const;
  FieldType type(const std::string& name) const;
  void remove(const std::string& name);

  // Adds (or replaces) a packed column (see the top of this file) and returns its raw values,
  // empty: the reader appends them; resize(n) with the values' count then sets the cloud's
  // size. T is one of PackedValues' element types. value = double(raw) when !scaled, else
  // double(raw) * scale + shift (the expression the readers used to store).
  template <typename T>
  std::vector<T>& add_packed(const std::string& name, FieldType type, bool scaled = false, double scale = 1,
                             double shift = 0);
  // Whether column i is still packed (tests, benchmarks).
  bool packed(std::size_t i) const;
  // The value of column i at `row`, without unpacking the column (writers, select()).
  double value(std::size_t i, std::size_t row) const;
  // Rows first .. first + count - 1 of column i into out, without unpacking the column.
  void values(std::size_t i, std::size_t first, std::size_t count, double* out) const;

  const std::vector<std::string>& names() const { return names_; }
  const std::vector<FieldType>& types() const { return types_; }
  std::vector<double>& col(std::size_t i) { return unpacked(i); }
  const std::vector<double>& col(std::size_t i) const { return unpacked(i); }

  // Throws DataError("<file>: field 'x' missing (<hint>)") unless every name is present.
  void require(const std::vector<std::string>& names, const std::string& file,
               const std::string& hint = "") const;

  // New cloud holding the rows `keep` (in that order), every field kept.
  PointCloud select(const std::vector<std::size_t>& keep) const;

  // Free-text comment lines (provenance); written as PCD/PLY comments.
  std::vector<std::string> comments;

 private:
  struct Column {
    std::vector<double> values;  // the column, once unpacked
    PackedValues packed;         // the column while packed
    bool scaled = false;
    double scale = 1, shift = 0;
    std::atomic<bool> is_packed{false};
    Column() = default;
    Column(const Column& o);
    Column& operator=(const Column& o);
  };
  std::size_t index(const std::string& name) const;  // npos-like: names_.size() when absent
  std::vector<double>& unpacked(std::size_t i) const;
  std::size_t size_ = 0;
  std::vector<std::string> names_;
  std::vector<FieldType> types_;
  // deque: add() never invalidates earlier columns. mutable: a const col() unpacks.
  mutable std::deque<Column> data_;
  mutable std::mutex unpack_;  // held while a column is unpacked or the cloud copied
};

// Calls f(first, count, columns) for the rows in blocks of `block`: columns[c][r] is column c at
// row first + r (PointCloud::values: packed columns stay packed). For writers.
template <typename F>
void for_each_block(const PointCloud& cloud, F f, std::size_t block = 4096) {
  const std::size_t nc = cloud.names().size();
  std::vector<std::vector<double>> buffers(nc, std::vector<double>(std::min(block, cloud.size())));
  std::vector<const double*> columns(nc);
  for (std::size_t c = 0; c < nc; ++c) columns[c] = buffers[c].data();
  for (std::size_t first = 0; first < cloud.size(); first += block) {
    const std::size_t k = std::min(block, cloud.size() - first);
    for (std::size_t c = 0; c < nc; ++c) cloud.values(c, first, k, buffers[c].data());
    f(first, k, columns);
  }
}

template <typename T>
std::vector<T>& PointCloud::add_packed(const std::string& name, FieldType type, bool scaled, double scale,
                                       double shift) {
  std::size_t i = index(name);
  if (i == names_.size()) {
    names_.push_back(name);
    types_.push_back(type);
    data_.emplace_back();
  }
  types_[i] = type;
  Column& c = data_[i];
  c.values = std::vector<double>();
  c.scaled = scaled;
  c.scale = scale;
  c.shift = shift;
  c.is_packed.store(true, std::memory_order_release);
  return c.packed.template emplace<std::vector<T>>();
}

}  // namespace canopy::formats
