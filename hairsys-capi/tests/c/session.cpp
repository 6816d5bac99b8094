// The C++ wrapper's driver: the scenario's groom through every frame (as session.c does),
// with RAII handles, spans and exceptions; writes every frame's positions, then the last
// frame's velocities (float32), for tests/c_programs.rs to compare with the Rust Session.
//
//   session_cpp SCENARIO OUTPUT THREADS
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <vector>

#include "hairsys.hpp"

extern "C" {
#include "scenario.h"
}

static void drive_frame(hairsys::Session& s, const Frame& f, uint32_t vertex_count) {
  if (f.kind == 0) {
    s.set_scalp_transform(f.scalp);
  } else {
    s.set_scalp_vertices({f.vertices, 3 * size_t(vertex_count)}, f.scalp);
  }
  s.set_collider_pose(0, f.collider);
  s.step();
}

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: session_cpp SCENARIO OUTPUT THREADS\n";
    return 2;
  }
  if (!hairsys::abi_compatible()) {
    std::cerr << "the library's ABI does not match the header's\n";
    return 3;
  }
  try {
    Scenario sc = read_scenario(argv[1]);
    HairsysGroomArrays arrays{};
    arrays.scalp_vertices = sc.vertices;
    arrays.scalp_vertex_count = sc.vertex_count;
    arrays.scalp_triangles = sc.triangles;
    arrays.scalp_triangle_count = sc.triangle_count;
    arrays.curve_points = sc.points;
    arrays.curve_point_count = sc.point_count;
    arrays.curve_counts = sc.counts;
    arrays.curve_count = sc.curve_count;
    HairsysCollider sphere{};
    sphere.shape = HAIRSYS_SHAPE_SPHERE;
    sphere.radius = sc.collider_radius;
    sphere.pose = sc.collider_pose;
    HairsysGroomOptions options = hairsys::Session::default_options();
    options.colliders = &sphere;
    options.collider_count = 1;
    options.collider_speed = 1.0;
    options.threads = uint32_t(std::atoi(argv[3]));

    auto s = hairsys::Session::from_groom(arrays, options);
    std::vector<std::vector<float>> frames;
    const uint32_t half = sc.frame_count / 2;
    std::vector<hairsys::Snapshot> snaps;
    for (uint32_t i = 0; i < sc.frame_count; i++) {
      drive_frame(s, sc.frames[i], sc.vertex_count);
      auto p = s.positions();
      frames.emplace_back(p.begin(), p.end());
      if (i + 1 == half) snaps.push_back(s.snapshot());
    }
    auto v = s.velocities();
    std::ofstream out(argv[2], std::ios::binary);
    for (const auto& f : frames) out.write(reinterpret_cast<const char*>(f.data()), f.size() * 4);
    out.write(reinterpret_cast<const char*>(v.data()), v.size() * 4);
    out.close();

    s.restore(snaps.at(0));
    if (s.info().frame != snaps[0].frame()) {
      std::cerr << "restore did not go back to the snapshot's frame\n";
      return 1;
    }
    for (uint32_t i = half; i < sc.frame_count; i++) {
      drive_frame(s, sc.frames[i], sc.vertex_count);
      auto p = s.positions();
      if (std::memcmp(p.data(), frames[i].data(), p.size() * 4) != 0) {
        std::cerr << "frame " << i << " after restore differs from the first pass\n";
        return 1;
      }
    }
    // A cache and children through the wrapper: the cache gives back the frame's bits.
    const std::string cache_path = std::string(argv[2]) + ".mcap";
    s.record(cache_path);
    drive_frame(s, sc.frames[sc.frame_count - 1], sc.vertex_count);
    const auto last = s.positions();
    const std::vector<float> want(last.begin(), last.end());
    if (s.finish_recording().frames != 2) {
      std::cerr << "the cache does not hold 2 frames\n";
      return 1;
    }
    hairsys::Cache cache(cache_path);
    const HairsysCacheInfo info = cache.info();
    std::vector<float> got(3 * info.point_count), velocities(3 * info.point_count);
    cache.read_frame(info.last_frame, got, velocities);
    if (got != want || cache.strand_offsets().size() != s.strand_offsets().size()) {
      std::cerr << "the cache's last frame is not the session's\n";
      return 1;
    }
    const auto kids = s.children(hairsys::Session::default_child_settings());
    const hairsys::ChildrenView k = kids.view();
    if (k.vertex_counts.empty() || k.vertex_counts.size() != k.parent.size() ||
        k.points.size() != 3 * k.widths.size()) {
      std::cerr << "the children's arrays do not agree in size\n";
      return 1;
    }
    hairsys::export_usd(cache_path, std::string(argv[2]) + ".usda");

    // An exception carries the code and the message.
    try {
      s.set_collider_pose(7, hairsys::identity());
      std::cerr << "collider 7 was accepted\n";
      return 1;
    } catch (const hairsys::Error& e) {
      if (e.code() != HAIRSYS_STATUS_BAD_ARGUMENT || std::strstr(e.what(), "collider 7") == nullptr) {
        std::cerr << "unexpected error " << e.code() << ": " << e.what() << "\n";
        return 1;
      }
    }
    free_scenario(&sc);
  } catch (const hairsys::Error& e) {
    std::cerr << "hairsys error " << e.code() << ": " << e.what() << "\n";
    return 1;
  }
  return 0;
}
