#pragma once
// Writing HDF5 objects in one call each: strings as UTF-8, datasets whole.
// Shared by the result file and the files derived from it.

#include <algorithm>
#include <string>
#include <vector>

#include "engine/io/h5_handle.hpp"

namespace granflow {

inline H5Handle string_type(std::size_t fixed_length = 0) {
  H5Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "copy string type");
  h5_check(H5Tset_size(type, fixed_length ? fixed_length : H5T_VARIABLE), "set string size");
  h5_check(H5Tset_cset(type, H5T_CSET_UTF8), "set string charset");
  return type;
}

inline void write_string_attribute(hid_t object, const std::string& name, const std::string& value) {
  H5Handle type = string_type();
  H5Handle space(H5Screate(H5S_SCALAR), H5Sclose, "create scalar space");
  if (H5Aexists(object, name.c_str()) > 0) h5_check(H5Adelete(object, name.c_str()), "replace attribute " + name);
  H5Handle attribute(H5Acreate2(object, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                     "create attribute " + name);
  const char* text = value.c_str();
  h5_check(H5Awrite(attribute, type, &text), "write attribute " + name);
}

inline void write_dataset(hid_t parent, const std::string& name, hid_t mem_type, const void* data,
                          const std::vector<hsize_t>& shape) {
  H5Handle space(shape.empty() ? H5Screate(H5S_SCALAR)
                               : H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr),
                 H5Sclose, "create space for " + name);
  H5Handle dataset(H5Dcreate2(parent, name.c_str(), mem_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                   H5Dclose, "create dataset " + name);
  h5_check(H5Dwrite(dataset, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "write dataset " + name);
}

template <class T>
void write_numeric_attribute(hid_t object, const std::string& name, hid_t mem_type, const std::vector<T>& values) {
  const hsize_t size = values.size();
  H5Handle space(values.size() == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &size, nullptr), H5Sclose,
                 "create attribute space");
  if (H5Aexists(object, name.c_str()) > 0) h5_check(H5Adelete(object, name.c_str()), "replace attribute " + name);
  H5Handle attribute(H5Acreate2(object, name.c_str(), mem_type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                     "create attribute " + name);
  h5_check(H5Awrite(attribute, mem_type, values.data()), "write attribute " + name);
}

inline void write_string_array_attribute(hid_t object, const std::string& name,
                                         const std::vector<std::string>& values) {
  std::size_t width = 1;
  for (const auto& v : values) width = std::max(width, v.size() + 1);
  std::vector<char> packed(width * values.size(), '\0');
  for (std::size_t k = 0; k < values.size(); ++k) values[k].copy(packed.data() + k * width, values[k].size());
  H5Handle type = string_type(width);
  h5_check(H5Tset_strpad(type, H5T_STR_NULLTERM), "set string padding");
  const hsize_t size = values.size();
  H5Handle space(H5Screate_simple(1, &size, nullptr), H5Sclose, "create attribute space");
  H5Handle attribute(H5Acreate2(object, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                     "create attribute " + name);
  h5_check(H5Awrite(attribute, type, packed.data()), "write attribute " + name);
}

// A dataspace of `shape`, wholly selected.
inline H5Handle simple_space(const std::vector<hsize_t>& shape, const std::string& what) {
  return H5Handle(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr), H5Sclose,
                  "create space of " + what);
}

// Dataset `name` (created with its parent groups) of `type` and `shape`,
// whose region selected in `mapped` reads the region selected in
// `source_space` of dataset `source` in file `source_file`: an HDF5 virtual
// dataset, nothing copied and none of the source's attributes seen. The
// rest reads `fill` (HDF5's zero where null).
inline void write_virtual_dataset(hid_t parent, const std::string& name, hid_t type, const std::vector<hsize_t>& shape,
                                  hid_t mapped, const std::string& source_file, const std::string& source,
                                  hid_t source_space, const void* fill = nullptr) {
  H5Handle properties(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "create properties of " + name);
  if (fill) h5_check(H5Pset_fill_value(properties, type, fill), "set fill value of " + name);
  h5_check(H5Pset_virtual(properties, mapped, source_file.c_str(), source.c_str(), source_space),
           "map " + name + " onto " + source);
  H5Handle links(H5Pcreate(H5P_LINK_CREATE), H5Pclose, "create link properties");
  h5_check(H5Pset_create_intermediate_group(links, 1), "set intermediate groups");
  const H5Handle space = simple_space(shape, name);
  H5Handle dataset(H5Dcreate2(parent, name.c_str(), type, space, links, properties, H5P_DEFAULT), H5Dclose,
                   "create " + name);
}

}  // namespace granflow
