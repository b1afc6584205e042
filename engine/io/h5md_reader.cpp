#include "engine/io/h5md_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <limits>

namespace granflow {

namespace {

std::vector<std::uint64_t> shape_of(hid_t dataset, const std::string& what) {
  H5Handle space(H5Dget_space(dataset), H5Sclose, "get space of " + what);
  const int rank = H5Sget_simple_extent_ndims(space);
  h5_check(rank, "get rank of " + what);
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  h5_check(H5Sget_simple_extent_dims(space, dims.data(), nullptr), "get extent of " + what);
  return {dims.begin(), dims.end()};
}

std::size_t element_count(const std::vector<std::uint64_t>& shape) {
  std::size_t count = 1;
  for (auto e : shape) count *= e;
  return count;
}

H5Handle variable_string_type() {
  H5Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "copy string type");
  h5_check(H5Tset_size(type, H5T_VARIABLE), "set string size");
  h5_check(H5Tset_cset(type, H5T_CSET_UTF8), "set string charset");
  return type;
}

// Every attribute read here is one value; a file with more (damaged or
// crafted) is refused before anything is copied into a one-value buffer.
void require_one_value(hid_t attribute, const std::string& what) {
  H5Handle space(H5Aget_space(attribute), H5Sclose, "get space of " + what);
  const hssize_t points = H5Sget_simple_extent_npoints(space);
  if (points != 1) throw H5Error(fmt::format("attribute {} holds {} values, expected one", what, points));
}

std::string read_string_attribute_of(hid_t object, const std::string& name, const std::string& what) {
  H5Handle attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + what);
  require_one_value(attribute, what);
  H5Handle file_type(H5Aget_type(attribute), H5Tclose, "get type of " + what);
  if (H5Tis_variable_str(file_type) > 0) {
    H5Handle type = variable_string_type();
    char* text = nullptr;
    h5_check(H5Aread(attribute, type, &text), "read attribute " + what);
    std::string out = text ? text : "";
    H5free_memory(text);
    return out;
  }
  if (H5Tget_class(file_type) != H5T_STRING) throw H5Error("attribute " + what + " is not a string");
  const std::size_t size = H5Tget_size(file_type);
  if (size == 0 || size > (1u << 20)) throw H5Error("attribute " + what + " has an impossible string size");
  std::string out(size, '\0');
  h5_check(H5Aread(attribute, file_type, out.data()), "read attribute " + what);
  return out.substr(0, out.find('\0'));
}

// HDF5 iteration callback (links or attributes) that collects the names.
template <class Info>
herr_t append_name(hid_t, const char* name, const Info*, void* names) {
  static_cast<std::vector<std::string>*>(names)->emplace_back(name);
  return 0;
}

struct VisitState {
  std::string text;
};

herr_t describe_object(hid_t location, const char* name, const H5O_info_t* info, void* data) {
  auto* state = static_cast<VisitState*>(data);
  if (info->type != H5O_TYPE_DATASET) return 0;
  H5Handle dataset(H5Dopen2(location, name, H5P_DEFAULT), H5Dclose, std::string("open ") + name);
  const auto shape = shape_of(dataset, name);
  H5Handle type(H5Dget_type(dataset), H5Tclose, "get dataset type");
  std::string shape_text;
  for (std::size_t k = 0; k < shape.size(); ++k) shape_text += (k ? " x " : "") + std::to_string(shape[k]);
  if (shape.empty()) shape_text = "scalar";
  const char* kind = "other";
  switch (H5Tget_class(type)) {
    case H5T_FLOAT: kind = "float"; break;
    case H5T_INTEGER: kind = "integer"; break;
    case H5T_STRING: kind = "string"; break;
    default: break;
  }
  std::string unit;
  if (H5Aexists(dataset, "unit") > 0) {
    try {
      unit = "  [" + read_string_attribute_of(dataset, "unit", std::string(name) + "@unit") + "]";
    } catch (const H5Error&) {
    }
  }
  state->text += fmt::format("  /{:<48} {:<16} {}{}\n", name, shape_text, kind, unit);
  return 0;
}

}  // namespace

H5mdReader::H5mdReader(const std::string& path) : path_(path) {
  h5_quiet();
  if (H5Fis_hdf5(path.c_str()) <= 0) throw H5Error("'" + path + "' is not an HDF5 file (or cannot be read)");
  file_ = H5Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open '" + path + "'");
}

bool H5mdReader::exists(const std::string& object_path) const {
  // H5Lexists needs every intermediate link to exist, so walk down.
  std::size_t position = 1;
  while (true) {
    const auto next = object_path.find('/', position);
    const std::string prefix = object_path.substr(0, next);
    if (H5Lexists(file_, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (next == std::string::npos) return true;
    position = next + 1;
  }
}

DoubleArray H5mdReader::doubles(const std::string& dataset_path) const {
  H5Handle dataset(H5Dopen2(file_, dataset_path.c_str(), H5P_DEFAULT), H5Dclose, "open " + dataset_path);
  DoubleArray out;
  out.shape = shape_of(dataset, dataset_path);
  out.values.resize(element_count(out.shape));
  h5_check(H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.values.data()),
           "read " + dataset_path);
  return out;
}

std::vector<double> H5mdReader::doubles(const std::string& dataset_path, std::uint64_t first,
                                       std::uint64_t count) const {
  H5Handle dataset(H5Dopen2(file_, dataset_path.c_str(), H5P_DEFAULT), H5Dclose, "open " + dataset_path);
  const auto shape = shape_of(dataset, dataset_path);
  if (shape.size() != 1 || first + count > shape[0])
    throw H5Error(fmt::format("{} has no values {}..{}", dataset_path, first, first + count));
  std::vector<double> out(count);
  if (count == 0) return out;
  const hsize_t start = first, size = count;
  H5Handle file_space(H5Dget_space(dataset), H5Sclose, "get space of " + dataset_path);
  h5_check(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, &start, nullptr, &size, nullptr),
           "select values of " + dataset_path);
  H5Handle memory_space(H5Screate_simple(1, &size, nullptr), H5Sclose, "create memory space");
  h5_check(H5Dread(dataset, H5T_NATIVE_DOUBLE, memory_space, file_space, H5P_DEFAULT, out.data()),
           "read " + dataset_path);
  return out;
}

DoubleArray H5mdReader::frame(const std::string& dataset_path, std::uint64_t index) const {
  return frame(dataset_path, index, 0, std::numeric_limits<std::uint64_t>::max());
}

DoubleArray H5mdReader::frame(const std::string& dataset_path, std::uint64_t index, std::uint64_t first_row,
                              std::uint64_t rows) const {
  H5Handle dataset(H5Dopen2(file_, dataset_path.c_str(), H5P_DEFAULT), H5Dclose, "open " + dataset_path);
  const auto shape = shape_of(dataset, dataset_path);
  if (shape.empty() || index >= shape.front())
    throw H5Error(fmt::format("{} has no entry {}", dataset_path, index));
  std::vector<hsize_t> start(shape.size(), 0), count(shape.begin(), shape.end());
  start[0] = index;
  count[0] = 1;
  if (shape.size() > 1) {
    if (first_row > shape[1]) throw H5Error(fmt::format("{} has no row {}", dataset_path, first_row));
    start[1] = first_row;
    count[1] = std::min<std::uint64_t>(rows, shape[1] - first_row);
  }
  H5Handle file_space(H5Dget_space(dataset), H5Sclose, "get space of " + dataset_path);
  h5_check(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr),
           "select entry of " + dataset_path);
  H5Handle memory_space(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr), H5Sclose,
                        "create memory space");
  DoubleArray out;
  out.shape.assign(count.begin() + 1, count.end());
  out.values.resize(element_count(out.shape));
  if (out.values.empty()) return out;
  h5_check(H5Dread(dataset, H5T_NATIVE_DOUBLE, memory_space, file_space, H5P_DEFAULT, out.values.data()),
           "read entry of " + dataset_path);
  return out;
}

std::vector<std::uint64_t> H5mdReader::shape(const std::string& dataset_path) const {
  H5Handle dataset(H5Dopen2(file_, dataset_path.c_str(), H5P_DEFAULT), H5Dclose, "open " + dataset_path);
  return shape_of(dataset, dataset_path);
}

std::vector<std::int64_t> H5mdReader::integers(const std::string& dataset_path) const {
  H5Handle dataset(H5Dopen2(file_, dataset_path.c_str(), H5P_DEFAULT), H5Dclose, "open " + dataset_path);
  std::vector<std::int64_t> out(element_count(shape_of(dataset, dataset_path)));
  h5_check(H5Dread(dataset, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), "read " + dataset_path);
  return out;
}

std::vector<std::string> H5mdReader::string_array(const std::string& dataset_path) const {
  H5Handle dataset(H5Dopen2(file_, dataset_path.c_str(), H5P_DEFAULT), H5Dclose, "open " + dataset_path);
  const auto count = element_count(shape_of(dataset, dataset_path));
  H5Handle type = variable_string_type();
  std::vector<char*> pointers(count, nullptr);
  h5_check(H5Dread(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()), "read " + dataset_path);
  std::vector<std::string> out;
  for (char* p : pointers) {
    out.emplace_back(p ? p : "");
    H5free_memory(p);
  }
  return out;
}

std::string H5mdReader::string_dataset(const std::string& dataset_path) const {
  const auto values = string_array(dataset_path);
  return values.empty() ? std::string() : values.front();
}

std::string H5mdReader::string_attribute(const std::string& object_path, const std::string& name) const {
  H5Handle object(H5Oopen(file_, object_path.c_str(), H5P_DEFAULT), H5Oclose, "open " + object_path);
  return read_string_attribute_of(object, name, object_path + "@" + name);
}

std::vector<std::string> H5mdReader::string_list_attribute(const std::string& object_path,
                                                          const std::string& name) const {
  const std::string what = object_path + "@" + name;
  H5Handle object(H5Oopen(file_, object_path.c_str(), H5P_DEFAULT), H5Oclose, "open " + object_path);
  H5Handle attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + what);
  H5Handle type(H5Aget_type(attribute), H5Tclose, "get type of " + what);
  if (H5Tget_class(type) != H5T_STRING || H5Tis_variable_str(type) > 0)
    throw H5Error("attribute " + what + " is not a list of fixed-length strings");
  const std::size_t width = H5Tget_size(type);
  H5Handle space(H5Aget_space(attribute), H5Sclose, "get space of " + what);
  const hssize_t count = H5Sget_simple_extent_npoints(space);
  if (width == 0 || width > 4096 || count < 0 || count > 4096) throw H5Error("attribute " + what + " has an impossible size");
  std::vector<char> packed(width * static_cast<std::size_t>(count));
  h5_check(H5Aread(attribute, type, packed.data()), "read attribute " + what);
  std::vector<std::string> out;
  for (hssize_t k = 0; k < count; ++k) {
    const char* begin = packed.data() + static_cast<std::size_t>(k) * width;
    out.emplace_back(begin, strnlen(begin, width));
  }
  return out;
}

double H5mdReader::double_attribute(const std::string& object_path, const std::string& name) const {
  H5Handle object(H5Oopen(file_, object_path.c_str(), H5P_DEFAULT), H5Oclose, "open " + object_path);
  H5Handle attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + name);
  require_one_value(attribute, object_path + "@" + name);
  double value = 0;
  h5_check(H5Aread(attribute, H5T_NATIVE_DOUBLE, &value), "read attribute " + name);
  return value;
}

std::int64_t H5mdReader::integer_attribute(const std::string& object_path, const std::string& name) const {
  H5Handle object(H5Oopen(file_, object_path.c_str(), H5P_DEFAULT), H5Oclose, "open " + object_path);
  H5Handle attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + name);
  require_one_value(attribute, object_path + "@" + name);
  std::int64_t value = 0;
  h5_check(H5Aread(attribute, H5T_NATIVE_INT64, &value), "read attribute " + name);
  return value;
}

std::vector<std::string> H5mdReader::members(const std::string& group_path) const {
  H5Handle group(H5Gopen2(file_, group_path.c_str(), H5P_DEFAULT), H5Gclose, "open " + group_path);
  std::vector<std::string> names;
  h5_check(H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr, append_name<H5L_info_t>, &names),
           "list " + group_path);
  return names;
}

std::vector<std::string> H5mdReader::attribute_names(const std::string& object_path) const {
  H5Handle object(H5Oopen(file_, object_path.c_str(), H5P_DEFAULT), H5Oclose, "open " + object_path);
  std::vector<std::string> names;
  h5_check(H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_INC, nullptr, append_name<H5A_info_t>, &names),
           "list attributes of " + object_path);
  return names;
}

std::string H5mdReader::attribute_text(const std::string& object_path, const std::string& name) const {
  const std::string what = object_path + "@" + name;
  H5Handle object(H5Oopen(file_, object_path.c_str(), H5P_DEFAULT), H5Oclose, "open " + object_path);
  H5Handle attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + what);
  H5Handle type(H5Aget_type(attribute), H5Tclose, "get type of " + what);
  const H5T_class_t kind = H5Tget_class(type);
  if (kind == H5T_STRING) {
    H5Handle space(H5Aget_space(attribute), H5Sclose, "get space of " + what);
    if (H5Sget_simple_extent_npoints(space) != 1) return "(list of strings)";
    return read_string_attribute_of(object, name, what);
  }
  if (kind != H5T_FLOAT && kind != H5T_INTEGER) return "(not a number or text)";
  H5Handle space(H5Aget_space(attribute), H5Sclose, "get space of " + what);
  const hssize_t points = H5Sget_simple_extent_npoints(space);
  if (points < 1 || points > 16) return fmt::format("({} values)", points);
  std::vector<double> values(static_cast<std::size_t>(points));
  h5_check(H5Aread(attribute, H5T_NATIVE_DOUBLE, values.data()), "read attribute " + what);
  std::string text;
  for (std::size_t k = 0; k < values.size(); ++k) text += fmt::format("{}{:.10g}", k ? ", " : "", values[k]);
  return text;
}

std::string H5mdReader::describe() const {
  VisitState state;
  h5_check(H5Ovisit(file_, H5_INDEX_NAME, H5_ITER_NATIVE, describe_object, &state), "walk " + path_);
  return state.text;
}

}  // namespace granflow
