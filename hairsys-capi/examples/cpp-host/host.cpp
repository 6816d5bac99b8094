// A C++ host of hairsys: the loop a Houdini SOP or a Maya node runs.
//
//   host SCALP_PATTERN FIRST LAST GROOM.obj OUT_DIR
//
// SCALP_PATTERN is a printf pattern of a deforming mesh sequence (OBJ, e.g. "head.%04d.obj"),
// read from frame FIRST to LAST; all frames share the first's topology. GROOM.obj holds the
// curves as OBJ polylines ("v" points, "l" lines, root first), in the same world space at frame
// FIRST. The host builds a session of the groom on the first frame's mesh, records
// OUT_DIR/hair.mcap, hands the session every later frame's vertices, steps, and writes the
// whole shot as OUT_DIR/hair.usda (the strands as BasisCurves, time codes = frames).
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "hairsys.hpp"

namespace {

// The parts of an OBJ file the host needs: vertices, triangles (fans of larger faces) and
// polylines.
struct Obj {
  std::vector<float> vertices;       // xyz interleaved
  std::vector<uint32_t> triangles;   // three indices each
  std::vector<std::vector<uint32_t>> lines;
};

// An OBJ index ("7", "7/1", "7//3", or negative from the end) as a 0-based vertex index.
uint32_t index_of(const std::string& word, size_t vertex_count) {
  long i = std::stol(word.substr(0, word.find('/')));
  if (i < 0) i += long(vertex_count) + 1;
  if (i < 1 || size_t(i) > vertex_count) throw std::runtime_error("OBJ index out of range: " + word);
  return uint32_t(i - 1);
}

Obj read_obj(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  Obj obj;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    if (tag == "v") {
      float x, y, z;
      words >> x >> y >> z;
      obj.vertices.insert(obj.vertices.end(), {x, y, z});
    } else if (tag == "f" || tag == "l") {
      std::vector<uint32_t> ids;
      for (std::string w; words >> w;) ids.push_back(index_of(w, obj.vertices.size() / 3));
      if (tag == "l") {
        obj.lines.push_back(ids);
      } else {
        for (size_t k = 2; k < ids.size(); k++) obj.triangles.insert(obj.triangles.end(), {ids[0], ids[k - 1], ids[k]});
      }
    }
  }
  return obj;
}

std::string frame_path(const std::string& pattern, int frame) {
  std::vector<char> buf(pattern.size() + 32);
  std::snprintf(buf.data(), buf.size(), pattern.c_str(), frame);
  return buf.data();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 6) {
    std::cerr << "usage: host SCALP_PATTERN FIRST LAST GROOM.obj OUT_DIR\n";
    return 2;
  }
  const std::string pattern = argv[1];
  const int first = std::atoi(argv[2]), last = std::atoi(argv[3]);
  const std::string out_dir = argv[5];
  if (!hairsys::abi_compatible()) {
    std::cerr << "libhairsys_capi's ABI does not match hairsys.h\n";
    return 2;
  }
  try {
    const Obj scalp = read_obj(frame_path(pattern, first));
    const Obj groom = read_obj(argv[4]);
    std::vector<float> points;
    std::vector<uint32_t> counts;
    for (const auto& l : groom.lines) {
      counts.push_back(uint32_t(l.size()));
      for (uint32_t i : l) points.insert(points.end(), &groom.vertices[3 * i], &groom.vertices[3 * i + 3]);
    }

    HairsysGroomArrays arrays{};
    arrays.scalp_vertices = scalp.vertices.data();
    arrays.scalp_vertex_count = scalp.vertices.size() / 3;
    arrays.scalp_triangles = scalp.triangles.data();
    arrays.scalp_triangle_count = scalp.triangles.size() / 3;
    arrays.curve_points = points.data();
    arrays.curve_point_count = points.size() / 3;
    arrays.curve_counts = counts.data();
    arrays.curve_count = counts.size();
    HairsysGroomOptions options = hairsys::Session::default_options();
    options.first_frame = uint32_t(first);
    options.goal_root = 0.3f;  // hold the groom a little, softer towards the tips
    options.scalp_collider = 1;

    auto session = hairsys::Session::from_groom(arrays, options);
    const std::string cache = out_dir + "/hair.mcap";
    session.record(cache, HAIRSYS_COMPRESSION_ZSTD);
    for (int frame = first + 1; frame <= last; frame++) {
      const Obj mesh = read_obj(frame_path(pattern, frame));
      session.set_scalp_vertices(mesh.vertices);  // world space: the identity body transform
      const HairsysFrameReport r = session.step();
      std::cout << "frame " << r.frame << ": " << r.substeps << " substeps, max stretch " << r.max_stretch
                << "\n";
    }
    const HairsysCacheSummary summary = session.finish_recording();
    hairsys::export_usd(cache, out_dir + "/hair.usda");
    std::cout << summary.frames << " frames of " << summary.strands << " strands in " << cache << " and "
              << out_dir << "/hair.usda\n";
  } catch (const hairsys::Error& e) {
    std::cerr << "hairsys: " << e.what() << " (status " << e.code() << ")\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "host: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
