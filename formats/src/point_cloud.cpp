#include "canopy/formats/point_cloud.h"

#include <stdexcept>

#include "canopy/common/error.h"

namespace canopy::formats {

void PointCloud::resize(std::size_t n) {
  size_ = n;
  for (auto& c : data_) c.resize(n, 0.0);
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
    return data_[i];
  }
  names_.push_back(name);
  types_.push_back(type);
  data_.emplace_back(size_, 0.0);
  return data_.back();
}

std::vector<double>& PointCloud::col(const std::string& name) {
  const std::size_t i = index(name);
  if (i == names_.size()) throw std::out_of_range("field '" + name + "' missing");
  return data_[i];
}

const std::vector<double>& PointCloud::col(const std::string& name) const {
  const std::size_t i = index(name);
  if (i == names_.size()) throw std::out_of_range("field '" + name + "' missing");
  return data_[i];
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
  for (std::size_t c = 0; c < data_.size(); ++c) {
    auto& dst = out.data_[c];
    dst.resize(keep.size());
    for (std::size_t r = 0; r < keep.size(); ++r) dst[r] = data_[c].at(keep[r]);
  }
  return out;
}

}  // namespace canopy::formats
