// In-memory point set with any set of named scalar fields (column-major, one
// std::vector<double> per field: every PCD/PLY scalar type up to 32 bits is exact in a double).
// Shared by PCD clouds and PLY mesh vertices.
#pragma once

#include <cstddef>
#include <deque>
#include <string>
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

class PointCloud {
 public:
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  // Resizes every column (new entries are 0).
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

  const std::vector<std::string>& names() const { return names_; }
  const std::vector<FieldType>& types() const { return types_; }
  std::vector<double>& col(std::size_t i) { return data_[i]; }
  const std::vector<double>& col(std::size_t i) const { return data_[i]; }

  // Throws DataError("<file>: field 'x' missing (<hint>)") unless every name is present.
  void require(const std::vector<std::string>& names, const std::string& file,
               const std::string& hint = "") const;

  // New cloud holding the rows `keep` (in that order), every field kept.
  PointCloud select(const std::vector<std::size_t>& keep) const;

  // Free-text comment lines (provenance); written as PCD/PLY comments.
  std::vector<std::string> comments;

 private:
  std::size_t index(const std::string& name) const;  // npos-like: names_.size() when absent
  std::size_t size_ = 0;
  std::vector<std::string> names_;
  std::vector<FieldType> types_;
  std::deque<std::vector<double>> data_;  // deque: add() never invalidates earlier columns
};

}  // namespace canopy::formats
