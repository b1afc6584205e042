#include "engine/particle_export.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

#include "engine/h5md_reader.hpp"
#include "engine/input_error.hpp"

namespace granflow {

namespace {

const std::string particles = "/particles/all";

struct FrameLayout {
  std::size_t frames = 0;
  std::size_t count = 0;
  std::size_t dimension = 0;
  bool box_per_frame = false;  // box/edges is a {step, time, value} element of D x D matrices
  std::vector<double> fixed_edges;
  std::vector<std::string> boundary;
};

FrameLayout layout_of(const H5mdReader& reader, const std::string& path) {
  if (!reader.exists(particles + "/position/value"))
    throw InputError(fmt::format("'{}' has no particle frames (/particles/all/position): run with "
                                 "output.positions = \"all\", \"first_last\" or \"final\"",
                                 path));
  const auto shape = reader.doubles(particles + "/position/time").shape;
  FrameLayout layout;
  layout.frames = shape.empty() ? 0 : shape.front();
  const auto first = reader.frame(particles + "/position/value", 0);
  if (first.shape.size() != 2 || first.shape[1] < 2 || first.shape[1] > 3)
    throw InputError(fmt::format("'{}': positions are not N x 2 or N x 3 per frame", path));
  layout.count = first.shape[0];
  layout.dimension = first.shape[1];
  layout.box_per_frame = reader.exists(particles + "/box/edges/value");
  if (!layout.box_per_frame && reader.exists(particles + "/box/edges"))
    layout.fixed_edges = reader.doubles(particles + "/box/edges").values;
  layout.boundary.assign(layout.dimension, "periodic");
  if (reader.exists(particles + "/box")) layout.boundary = reader.string_list_attribute(particles + "/box", "boundary");
  return layout;
}

std::vector<double> edges_of(const H5mdReader& reader, const FrameLayout& layout, std::size_t frame) {
  if (!layout.box_per_frame) return layout.fixed_edges;
  const auto matrix = reader.frame(particles + "/box/edges/value", frame).values;
  std::vector<double> edges(layout.dimension);
  for (std::size_t a = 0; a < layout.dimension; ++a) edges[a] = matrix[a * layout.dimension + a];
  return edges;
}

std::optional<std::vector<double>> constant(const H5mdReader& reader, const std::string& name) {
  if (!reader.exists(particles + "/" + name)) return std::nullopt;
  return reader.doubles(particles + "/" + name).values;
}

std::string relative_to(const std::string& target, const std::string& from_file) {
  const auto base = std::filesystem::absolute(from_file).parent_path();
  return std::filesystem::relative(std::filesystem::absolute(target), base).string();
}

}  // namespace

std::size_t export_extended_xyz(const std::string& result, const std::string& output) {
  const H5mdReader reader(result);
  const FrameLayout layout = layout_of(reader, result);
  const auto radius = constant(reader, "radius");
  const auto species = constant(reader, "species");
  const bool velocities = reader.exists(particles + "/velocity/value");
  const auto times = reader.doubles(particles + "/position/time").values;
  std::string pbc;
  for (std::size_t a = 0; a < 3; ++a)
    pbc += std::string(a ? " " : "") + (a < layout.boundary.size() && layout.boundary[a] == "periodic" ? "T" : "F");
  const std::string partial = output + ".partial";
  std::FILE* out = std::fopen(partial.c_str(), "w");
  if (!out) throw InputError(fmt::format("cannot write '{}'", partial));
  std::string properties = "species:S:1:pos:R:3";
  if (velocities) properties += ":velo:R:3";
  if (radius) properties += ":radius:R:1";
  properties += ":id:I:1";
  for (std::size_t f = 0; f < layout.frames; ++f) {
    const auto position = reader.frame(particles + "/position/value", f).values;
    const auto velocity = velocities ? reader.frame(particles + "/velocity/value", f).values : std::vector<double>{};
    const auto edges = edges_of(reader, layout, f);
    // 2D: the plane z = 0 in a lattice whose third vector is a unit normal.
    const double lz = layout.dimension == 3 && edges.size() == 3 ? edges[2] : 1.0;
    fmt::print(out, "{}\nLattice=\"{:.17g} 0 0 0 {:.17g} 0 0 0 {:.17g}\" Properties={} Time={:.17g} pbc=\"{}\"\n",
               layout.count, edges.size() > 0 ? edges[0] : 1.0, edges.size() > 1 ? edges[1] : 1.0, lz, properties,
               times[f], pbc);
    const std::size_t d = layout.dimension;
    for (std::size_t i = 0; i < layout.count; ++i) {
      fmt::print(out, "S{}", species ? static_cast<int>((*species)[i]) : 0);
      for (std::size_t a = 0; a < 3; ++a) fmt::print(out, " {:.10g}", a < d ? position[i * d + a] : 0.0);
      if (velocities)
        for (std::size_t a = 0; a < 3; ++a) fmt::print(out, " {:.10g}", a < d ? velocity[i * d + a] : 0.0);
      if (radius) fmt::print(out, " {:.10g}", (*radius)[i]);
      fmt::print(out, " {}\n", i);
    }
  }
  const bool written = std::fflush(out) == 0 && !std::ferror(out);
  std::fclose(out);
  if (!written) {
    std::filesystem::remove(partial);
    throw InputError(fmt::format("cannot write '{}' (disk full?)", partial));
  }
  std::filesystem::rename(partial, output);
  return layout.frames;
}

std::size_t export_xdmf(const std::string& result, const std::string& output) {
  const H5mdReader reader(result);
  const FrameLayout layout = layout_of(reader, result);
  const auto times = reader.doubles(particles + "/position/time").values;
  const std::string file = relative_to(result, output);
  const std::size_t n = layout.count, d = layout.dimension, frames = layout.frames;
  // One frame of a [frames, N, components] dataset, selected in place.
  const auto slab = [&](const std::string& element, std::size_t f, std::size_t components) {
    const std::string dims = components > 1 ? fmt::format("{} {}", n, components) : fmt::format("{}", n);
    const std::string full = components > 1 ? fmt::format("{} {} {}", frames, n, components)
                                            : fmt::format("{} {}", frames, n);
    const std::string rank_rows =
        components > 1 ? fmt::format("{} 0 0 1 1 1 1 {} {}", f, n, components) : fmt::format("{} 0 1 1 1 {}", f, n);
    return fmt::format(
        "<DataItem ItemType=\"HyperSlab\" Dimensions=\"{}\">\n"
        "          <DataItem Dimensions=\"3 {}\" Format=\"XML\">{}</DataItem>\n"
        "          <DataItem Dimensions=\"{}\" NumberType=\"{}\" Precision=\"{}\" Format=\"HDF\">{}:{}/{}/value</DataItem>\n"
        "        </DataItem>",
        dims, components > 1 ? 3 : 2, rank_rows, full, element == "image" ? "Int" : "Float",
        element == "image" ? 4 : 8, file, particles, element);
  };
  const auto constant_item = [&](const std::string& name, bool integer) {
    return fmt::format("<DataItem Dimensions=\"{}\" NumberType=\"{}\" Precision=\"{}\" Format=\"HDF\">{}:{}/{}</DataItem>",
                       n, integer ? "Int" : "Float", integer ? 4 : 8, file, particles, name);
  };
  std::string text = "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
                     "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t f = 0; f < frames; ++f) {
    text += fmt::format("    <Grid Name=\"frame {}\" GridType=\"Uniform\">\n      <Time Value=\"{:.17g}\"/>\n", f,
                        times[f]);
    text += fmt::format("      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\"/>\n", n);
    text += fmt::format("      <Geometry GeometryType=\"{}\">\n        {}\n      </Geometry>\n", d == 3 ? "XYZ" : "XY",
                        slab("position", f, d));
    const auto attribute = [&](const std::string& name, const std::string& type, const std::string& item) {
      text += fmt::format("      <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">\n        {}\n      </Attribute>\n",
                          name, type, item);
    };
    // ParaView's vectors have three components: in 2D the velocity is a two-column matrix.
    if (reader.exists(particles + "/velocity/value")) attribute("velocity", d == 3 ? "Vector" : "Matrix", slab("velocity", f, d));
    if (reader.exists(particles + "/image/value")) attribute("image", d == 3 ? "Vector" : "Matrix", slab("image", f, d));
    if (reader.exists(particles + "/radius")) attribute("radius", "Scalar", constant_item("radius", false));
    if (reader.exists(particles + "/mass")) attribute("mass", "Scalar", constant_item("mass", false));
    if (reader.exists(particles + "/species")) attribute("species", "Scalar", constant_item("species", true));
    if (reader.exists(particles + "/id")) attribute("id", "Scalar", constant_item("id", true));
    text += "    </Grid>\n";
  }
  text += "    </Grid>\n  </Domain>\n</Xdmf>\n";
  const std::string partial = output + ".partial";
  {
    std::ofstream out(partial);
    out << text;
    if (!out.flush()) {
      std::filesystem::remove(partial);
      throw InputError(fmt::format("cannot write '{}'", partial));
    }
  }
  std::filesystem::rename(partial, output);
  return frames;
}

}  // namespace granflow
