// The HDF5 writing helpers: attributes (strings, numbers, string lists,
// replaced when written again) and datasets, read back with the reader.

#include "engine/io/h5_write.hpp"

#include <gtest/gtest.h>

#include "engine/io/h5md_reader.hpp"
#include "tests/scratch_directory.hpp"

namespace granflow {
namespace {

TEST(H5Write, AttributesAndDatasetsReadBack) {
  ScratchDirectory scratch("granflow_h5_write_test_");
  const std::string path = (scratch.path / "plain.h5").string();
  {
    H5Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "create");
    write_string_attribute(file, "author", "first");
    write_string_attribute(file, "author", "second");  // replaces
    write_numeric_attribute(file, "edges", H5T_NATIVE_DOUBLE, std::vector<double>{1.0, 2.5});
    write_numeric_attribute(file, "dimension", H5T_NATIVE_INT64, std::vector<std::int64_t>{3});
    write_string_array_attribute(file, "boundary", {"periodic", "none"});
    const std::vector<double> values{1, 2, 3, 4, 5, 6};
    write_dataset(file, "matrix", H5T_NATIVE_DOUBLE, values.data(), {2, 3});
    file.close("close");
  }
  const H5mdReader reader(path);
  EXPECT_EQ(reader.string_attribute("/", "author"), "second");
  EXPECT_EQ(reader.attribute_text("/", "edges"), "1, 2.5");
  EXPECT_EQ(reader.integer_attribute("/", "dimension"), 3);
  EXPECT_EQ(reader.string_list_attribute("/", "boundary"), (std::vector<std::string>{"periodic", "none"}));
  const DoubleArray matrix = reader.doubles("/matrix");
  EXPECT_EQ(matrix.shape, (std::vector<std::uint64_t>{2, 3}));
  EXPECT_EQ(matrix.values, (std::vector<double>{1, 2, 3, 4, 5, 6}));
}

}  // namespace
}  // namespace granflow
