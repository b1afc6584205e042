#include "engine/io/xdmf_export.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

#include "engine/core/input_error.hpp"
#include "engine/io/h5_handle.hpp"
#include "engine/io/h5_write.hpp"
#include "engine/io/h5md_reader.hpp"
#include "engine/io/particle_frames.hpp"

namespace granflow {

namespace {

std::string relative_to(const std::string& target, const std::string& from_file) {
  const auto base = std::filesystem::absolute(from_file).parent_path();
  return std::filesystem::relative(std::filesystem::absolute(target), base).string();
}

std::string join(const std::vector<hsize_t>& values) {
  std::string text;
  for (hsize_t v : values) {
    if (!text.empty()) text += ' ';
    text += std::to_string(v);
  }
  return text;
}

// The companion file of virtual datasets, written under a temporary name and
// moved into place by finish().
class VirtualFrames {
 public:
  VirtualFrames(const std::string& path, const std::string& result)
      : path_(path), partial_(path + ".partial"), source_(relative_to(result, path)) {
    file_ = H5Handle(H5Fcreate(partial_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                     "create " + partial_);
  }
  ~VirtualFrames() {
    if (file_.valid()) {
      file_ = H5Handle();
      std::error_code ignored;
      std::filesystem::remove(partial_, ignored);
    }
  }

  const std::string& name() const { return name_; }

  // Frame `frame` of the result's dataset `source` (shape [frames, rest...])
  // as dataset `name`, its last axis padded with zeros to `width` if longer.
  void map(const std::string& name, const std::string& source, const std::vector<hsize_t>& shape, hsize_t frame,
           hid_t type, hsize_t width) {
    std::vector<hsize_t> slice(shape.begin() + 1, shape.end());
    std::vector<hsize_t> virtual_shape = slice;
    if (width > virtual_shape.back()) virtual_shape.back() = width;
    const H5Handle virtual_space = simple_space(virtual_shape, name);
    const std::vector<hsize_t> origin(slice.size(), 0);
    h5_check(H5Sselect_hyperslab(virtual_space, H5S_SELECT_SET, origin.data(), nullptr, slice.data(), nullptr),
             "select " + name);
    const H5Handle source_space = simple_space(shape, source);
    std::vector<hsize_t> start(shape.size(), 0), count = shape;
    start[0] = frame;
    count[0] = 1;
    h5_check(H5Sselect_hyperslab(source_space, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr),
             "select frame of " + source);
    const double zero = 0.0;
    const std::int32_t zero_integer = 0;
    write_virtual_dataset(file_, name, type, virtual_shape, virtual_space, source_, source, source_space,
                          type == H5T_NATIVE_DOUBLE ? static_cast<const void*>(&zero)
                                                    : static_cast<const void*>(&zero_integer));
  }

  // Vertex k of the point cloud is particle k.
  void write_connectivity(std::size_t count) {
    std::vector<std::int32_t> vertices(count);
    for (std::size_t i = 0; i < count; ++i) vertices[i] = static_cast<std::int32_t>(i);
    write_dataset(file_, "connectivity", H5T_NATIVE_INT32, vertices.data(), {count});
  }

  void finish() {
    file_.close("close " + partial_);
    std::filesystem::rename(partial_, path_);
  }

 private:
  std::string path_, partial_, source_;
  std::string name_ = std::filesystem::path(path_).filename().string();
  H5Handle file_;
};

std::string data_item(const std::string& file, const std::string& dataset, const std::vector<hsize_t>& shape,
                      bool integer) {
  return fmt::format("<DataItem Dimensions=\"{}\" NumberType=\"{}\" Precision=\"{}\" Format=\"HDF\">{}:{}</DataItem>",
                     join(shape), integer ? "Int" : "Float", integer ? 4 : 8, file, dataset);
}

std::string attribute(const std::string& name, bool vector, const std::string& center, const std::string& item) {
  return fmt::format("      <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"{}\">\n        {}\n      </Attribute>\n",
                     name, vector ? "Vector" : "Scalar", center, item);
}

std::string particle_grids(const H5mdReader& reader, const ParticleFrames& frames, const std::string& result,
                           const std::string& output, VirtualFrames& companion) {
  const std::string& p = particles_group;
  const std::string result_name = relative_to(result, output);
  const hsize_t n = frames.count, d = frames.dimension;
  const std::vector<hsize_t> vectors{n, 3}, scalars{n};
  companion.write_connectivity(frames.count);
  std::string text = "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  const std::vector<hsize_t> frame_shape{frames.frames, n, d};
  for (std::size_t f = 0; f < frames.frames; ++f) {
    const std::string frame = fmt::format("/particles/{}", f);
    companion.map(frame + "/position", p + "/position/value", frame_shape, f, H5T_NATIVE_DOUBLE, 3);
    text += fmt::format("    <Grid Name=\"frame {}\" GridType=\"Uniform\">\n      <Time Value=\"{:.17g}\"/>\n", f,
                        frames.times[f]);
    text += fmt::format("      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" NodesPerElement=\"1\">\n"
                        "        {}\n      </Topology>\n",
                        n, data_item(companion.name(), "/connectivity", scalars, true));
    text += fmt::format("      <Geometry GeometryType=\"XYZ\">\n        {}\n      </Geometry>\n",
                        data_item(companion.name(), frame + "/position", vectors, false));
    for (const auto& [element, integer] : {std::pair{"velocity", false}, {"image", true}}) {
      if (!reader.exists(p + "/" + element + "/value")) continue;
      companion.map(frame + "/" + element, p + "/" + element + "/value", frame_shape, f,
                    integer ? H5T_NATIVE_INT32 : H5T_NATIVE_DOUBLE, 3);
      text += attribute(element, true, "Node",
                        data_item(companion.name(), frame + "/" + element, vectors, integer));
    }
    for (const auto& [constant, integer] :
         {std::pair{"radius", false}, {"mass", false}, {"species", true}, {"id", true}})
      if (reader.exists(p + "/" + constant))
        text += attribute(constant, false, "Node", data_item(result_name, p + "/" + constant, scalars, integer));
    text += "    </Grid>\n";
  }
  return text + "    </Grid>\n";
}

std::string field_grids(const std::vector<std::size_t>& cells, const std::vector<double>& times,
                        const std::vector<GridField>& fields, VirtualFrames& companion) {
  const std::size_t d = cells.size();
  std::vector<hsize_t> cells_zyx, nodes_zyx;
  for (std::size_t a = d; a-- > 0;) {
    cells_zyx.push_back(cells[a]);
    nodes_zyx.push_back(cells[a] + 1);
  }
  std::string text = "    <Grid Name=\"fields\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t f = 0; f < times.size(); ++f) {
    text += fmt::format("    <Grid Name=\"frame {}\" GridType=\"Uniform\">\n      <Time Value=\"{:.17g}\"/>\n", f,
                        times[f]);
    text += fmt::format("      <Topology TopologyType=\"{}\" Dimensions=\"{}\"/>\n",
                        d == 3 ? "3DCoRectMesh" : "2DCoRectMesh", join(nodes_zyx));
    // Cell k spans [k, k + 1) along each axis: origin 0, spacing 1 (in z, y, x order).
    text += fmt::format("      <Geometry GeometryType=\"{}\">\n"
                        "        <DataItem Dimensions=\"{}\" Format=\"XML\">{}</DataItem>\n"
                        "        <DataItem Dimensions=\"{}\" Format=\"XML\">{}</DataItem>\n      </Geometry>\n",
                        d == 3 ? "ORIGIN_DXDYDZ" : "ORIGIN_DXDY", d, d == 3 ? "0 0 0" : "0 0", d,
                        d == 3 ? "1 1 1" : "1 1");
    for (const auto& field : fields) {
      std::vector<hsize_t> source_shape{times.size()};
      source_shape.insert(source_shape.end(), cells_zyx.begin(), cells_zyx.end());
      std::vector<hsize_t> shape = cells_zyx;
      if (field.components > 1) {
        source_shape.push_back(field.components);
        shape.push_back(3);
      }
      const std::string name = fmt::format("/fields/{}/{}", f, field.name);
      companion.map(name, "/fields/" + field.name + "/value", source_shape, f, H5T_NATIVE_DOUBLE,
                    field.components > 1 ? 3 : 1);
      text += attribute(field.name, field.components > 1, "Cell", data_item(companion.name(), name, shape, false));
    }
    text += "    </Grid>\n";
  }
  return text + "    </Grid>\n";
}

void write_text(const std::string& path, const std::string& text) {
  const std::string partial = path + ".partial";
  {
    std::ofstream out(partial);
    out << text;
    if (!out.flush()) {
      std::error_code ignored;
      std::filesystem::remove(partial, ignored);
      throw InputError(fmt::format("cannot write '{}'", partial));
    }
  }
  std::filesystem::rename(partial, path);
}

std::string document(const std::string& grids) {
  return "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n" + grids + "  </Domain>\n</Xdmf>\n";
}

}  // namespace

std::size_t export_xdmf(const std::string& result, const std::string& output) {
  const H5mdReader reader(result);
  const bool particles = reader.exists(particles_group + "/position/value");
  const bool fields = reader.exists("/fields/density/value");
  if (!particles && !fields)
    throw InputError(fmt::format("'{}' has neither particle frames ({}/position: run with output.positions = "
                                 "\"all\", \"first_last\" or \"final\") nor fields (/fields: fields.every_steps > 0)",
                                 result, particles_group));
  VirtualFrames companion(output + ".h5", result);
  std::string grids;
  std::size_t frames = 0;
  if (particles) {
    const auto layout = ParticleFrames::read(reader, result);
    grids += particle_grids(reader, layout, result, output, companion);
    frames = layout.frames;
  }
  if (fields) {
    const auto shape = reader.shape("/fields/density/value");
    std::vector<std::size_t> cells;
    for (std::size_t a = shape.size(); a-- > 1;) cells.push_back(shape[a]);
    std::vector<GridField> list;
    for (const auto& name : reader.members("/fields"))
      list.push_back({name, reader.shape("/fields/" + name + "/value").size() > shape.size()
                                ? static_cast<std::size_t>(reader.shape("/fields/" + name + "/value").back())
                                : 1});
    const auto times = reader.doubles("/fields/density/time").values;
    grids += field_grids(cells, times, list, companion);
    frames = std::max(frames, times.size());
  }
  companion.finish();
  write_text(output, document(grids));
  return frames;
}

void write_field_xdmf(const std::string& result, const std::string& output, const std::vector<std::size_t>& cells,
                      const std::vector<double>& times, const std::vector<GridField>& fields) {
  VirtualFrames companion(output + ".h5", result);
  const std::string grids = field_grids(cells, times, fields, companion);
  companion.finish();
  write_text(output, document(grids));
}

}  // namespace granflow
