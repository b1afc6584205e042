#pragma once
// Reads back what H5mdFile wrote: for `granflow info`, for tests and for tools.

#include <cstdint>
#include <string>
#include <vector>

#include "engine/io/h5_handle.hpp"

namespace granflow {

struct DoubleArray {
  std::vector<double> values;
  std::vector<std::uint64_t> shape;
};

class H5mdReader {
 public:
  explicit H5mdReader(const std::string& path);

  bool exists(const std::string& object_path) const;
  DoubleArray doubles(const std::string& dataset_path) const;
  // Values [first, first + count) of a 1D dataset.
  std::vector<double> doubles(const std::string& dataset_path, std::uint64_t first, std::uint64_t count) const;
  // A dataset's shape, without reading it.
  std::vector<std::uint64_t> shape(const std::string& dataset_path) const;
  std::vector<std::int64_t> integers(const std::string& dataset_path) const;
  // Entry `index` along the first axis of a dataset (one frame of a series).
  DoubleArray frame(const std::string& dataset_path, std::uint64_t index) const;
  // The same, only `rows` rows (along its second axis, the particles) from `first_row`.
  DoubleArray frame(const std::string& dataset_path, std::uint64_t index, std::uint64_t first_row,
                    std::uint64_t rows) const;
  std::string string_dataset(const std::string& dataset_path) const;
  std::vector<std::string> string_array(const std::string& dataset_path) const;
  std::string string_attribute(const std::string& object_path, const std::string& name) const;
  // A list of fixed-length strings (the box's boundary words).
  std::vector<std::string> string_list_attribute(const std::string& object_path, const std::string& name) const;
  double double_attribute(const std::string& object_path, const std::string& name) const;
  std::int64_t integer_attribute(const std::string& object_path, const std::string& name) const;

  // Names of a group's members and of an object's attributes, in name order.
  std::vector<std::string> members(const std::string& group_path) const;
  std::vector<std::string> attribute_names(const std::string& object_path) const;

  // An attribute as text: numbers (up to 16 of them) or a string.
  std::string attribute_text(const std::string& object_path, const std::string& name) const;

  // One line per dataset: path, shape and type, in file order.
  std::string describe() const;

 private:
  std::string path_;
  H5Handle file_;
};

}  // namespace granflow
