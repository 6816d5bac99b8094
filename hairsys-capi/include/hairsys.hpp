// hairsys.hpp: a header-only C++20 wrapper over hairsys.h.
//
// - RAII: Session, Snapshot, Children and Cache own their C handle (move-only) and destroy it.
// - Views: positions(), velocities(), strand_offsets() and Children::view() are std::spans
//   over the library's memory, without a copy; valid until the next call that changes the
//   object they came from (set_*, step, restore, record), or its destruction.
// - Errors: every failed call throws hairsys::Error, carrying the HairsysStatus code and the
//   library's message (which names the argument and the fix).
// - Threads, units, layouts and ownership: as hairsys.h says. Point arrays are float xyz
//   interleaved: a span of 3 * points floats.
#ifndef HAIRSYS_HPP
#define HAIRSYS_HPP

#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

#include "hairsys.h"

namespace hairsys {

/// A failed hairsys call: the status code and the library's message.
class Error : public std::runtime_error {
 public:
  Error(HairsysStatus code, const std::string& message)
      : std::runtime_error(message), code_(code) {}
  /// The status the call returned.
  HairsysStatus code() const noexcept { return code_; }

 private:
  HairsysStatus code_;
};

/// Throws hairsys::Error unless `status` is HAIRSYS_STATUS_OK.
inline void check(HairsysStatus status) {
  if (status != HAIRSYS_STATUS_OK) {
    throw Error(status, hairsys_last_error_message());
  }
}

/// Whether the library loaded runs a host built against this header (same major, minor at
/// least the header's).
inline bool abi_compatible() noexcept {
  const uint32_t v = hairsys_abi_version();
  // Signed, so a header of minor 0 compiles without an always-true comparison warning.
  const int64_t minor = int64_t(v & 0xffffu), wanted = int64_t(HAIRSYS_ABI_VERSION_MINOR);
  return (v >> 16) == HAIRSYS_ABI_VERSION_MAJOR && minor >= wanted;
}

/// The identity transform.
inline HairsysTransform identity() noexcept { return HairsysTransform{{0, 0, 0}, {0, 0, 0, 1}}; }

/// Points in a span of xyz floats; throws HAIRSYS_STATUS_BAD_LENGTH when its size is not a
/// multiple of 3.
inline size_t points_in(std::span<const float> xyz, const char* argument) {
  if (xyz.size() % 3 != 0) {
    throw Error(HAIRSYS_STATUS_BAD_LENGTH,
                std::string(argument) + ": holds " + std::to_string(xyz.size()) +
                    " floats, not a multiple of 3: give xyz interleaved points");
  }
  return xyz.size() / 3;
}

namespace detail {
struct SessionDelete {
  void operator()(HairsysSession* p) const noexcept { hairsys_session_destroy(p); }
};
struct SnapshotDelete {
  void operator()(HairsysSnapshot* p) const noexcept { hairsys_snapshot_destroy(p); }
};
struct ChildrenDelete {
  void operator()(HairsysChildren* p) const noexcept { hairsys_children_destroy(p); }
};
struct CacheDelete {
  void operator()(HairsysCache* p) const noexcept { hairsys_cache_destroy(p); }
};
}  // namespace detail

/// A copy of a session's state at one frame.
class Snapshot {
 public:
  explicit Snapshot(HairsysSnapshot* raw) : raw_(raw) {}
  /// The frame it holds.
  uint32_t frame() const {
    uint32_t f = 0;
    check(hairsys_snapshot_frame(raw_.get(), &f));
    return f;
  }
  const HairsysSnapshot* get() const noexcept { return raw_.get(); }

 private:
  std::unique_ptr<HairsysSnapshot, detail::SnapshotDelete> raw_;
};

/// Render children's flat arrays, viewed without a copy.
struct ChildrenView {
  std::span<const uint32_t> vertex_counts;  ///< points per child curve
  std::span<const float> points;            ///< xyz interleaved, m
  std::span<const float> widths;            ///< one per point, m
  std::span<const uint32_t> parent;         ///< the strand each child follows
  std::span<const float> root_uv;           ///< uv per child; empty without scalp UVs
};

/// Render children of a frame; owns its buffers.
class Children {
 public:
  explicit Children(HairsysChildren* raw) : raw_(raw) {}
  /// Views of the arrays, valid while this object lives.
  ChildrenView view() const {
    HairsysChildrenView v{};
    check(hairsys_children_view(raw_.get(), &v));
    return ChildrenView{
        {v.vertex_counts, v.curve_count},
        {v.points, v.point_count * 3},
        {v.widths, v.point_count},
        {v.parent, v.curve_count},
        v.root_uv ? std::span<const float>(v.root_uv, v.curve_count * 2) : std::span<const float>(),
    };
  }

 private:
  std::unique_ptr<HairsysChildren, detail::ChildrenDelete> raw_;
};

/// A simulation session (see hairsys.h).
class Session {
 public:
  /// The scene file at `path` (nullptr: the built-in default scene), on `threads` workers of
  /// its own (0: the shared pool).
  static Session from_scene(const char* path = nullptr, uint32_t threads = 0) {
    HairsysSession* raw = nullptr;
    check(hairsys_session_from_scene(path, threads, &raw));
    return Session(raw);
  }
  static Session from_scene(const std::string& path, uint32_t threads = 0) {
    return from_scene(path.c_str(), threads);
  }
  /// The host's groom arrays, simulated as `options` say (start from default_options()).
  static Session from_groom(const HairsysGroomArrays& arrays, const HairsysGroomOptions& options) {
    HairsysSession* raw = nullptr;
    check(hairsys_session_from_groom(&arrays, &options, &raw));
    return Session(raw);
  }
  /// The default options of a groom session.
  static HairsysGroomOptions default_options() {
    HairsysGroomOptions o{};
    check(hairsys_groom_options_default(&o));
    return o;
  }

  /// Frame, fps and sizes.
  HairsysSessionInfo info() const {
    HairsysSessionInfo i{};
    check(hairsys_session_info(raw_.get(), &i));
    return i;
  }
  /// The scalp's rigid transform for the next frame.
  void set_scalp_transform(const HairsysTransform& t) {
    check(hairsys_session_set_scalp_transform(raw_.get(), &t));
  }
  /// Deformed scalp vertices (body space, xyz) for the next frame, placed by `body`.
  void set_scalp_vertices(std::span<const float> xyz, const HairsysTransform& body = identity()) {
    const size_t n = points_in(xyz, "vertices");
    check(hairsys_session_set_scalp_vertices(raw_.get(), xyz.data(), n, &body));
  }
  /// Collider `id`'s pose at the end of the next frame.
  void set_collider_pose(uint32_t id, const HairsysTransform& pose) {
    check(hairsys_session_set_collider_pose(raw_.get(), id, &pose));
  }
  /// Mesh collider `id`'s body-space vertices (xyz) at the end of the next frame.
  void set_collider_vertices(uint32_t id, std::span<const float> xyz) {
    const size_t n = points_in(xyz, "vertices");
    check(hairsys_session_set_collider_vertices(raw_.get(), id, xyz.data(), n));
  }
  /// The material a host may change between frames.
  HairsysParams params() const {
    HairsysParams p{};
    check(hairsys_session_params(raw_.get(), &p));
    return p;
  }
  void set_params(const HairsysParams& p) { check(hairsys_session_set_params(raw_.get(), &p)); }
  /// Advances one frame.
  HairsysFrameReport step() {
    HairsysFrameReport r{};
    check(hairsys_session_step(raw_.get(), &r));
    return r;
  }
  /// Every point's position, xyz interleaved, m.
  std::span<const float> positions() const {
    HairsysPointsView v{};
    check(hairsys_session_positions(raw_.get(), &v));
    return {v.xyz, v.count * 3};
  }
  /// Every point's velocity, xyz interleaved, m/s.
  std::span<const float> velocities() const {
    HairsysPointsView v{};
    check(hairsys_session_velocities(raw_.get(), &v));
    return {v.xyz, v.count * 3};
  }
  /// Strands + 1 offsets: strand s is points offsets[s] to offsets[s + 1] - 1.
  std::span<const uint32_t> strand_offsets() const {
    HairsysIndexView v{};
    check(hairsys_session_strand_offsets(raw_.get(), &v));
    return {v.data, v.count};
  }
  /// A copy of the state at the current frame.
  Snapshot snapshot() const {
    HairsysSnapshot* raw = nullptr;
    check(hairsys_session_snapshot(raw_.get(), &raw));
    return Snapshot(raw);
  }
  /// Back to `snapshot`'s state.
  void restore(const Snapshot& snapshot) {
    check(hairsys_session_restore(raw_.get(), snapshot.get()));
  }
  /// Starts recording a cache at `path`.
  void record(const std::string& path, uint32_t compression = HAIRSYS_COMPRESSION_NONE,
              bool quantize = false) {
    check(hairsys_session_record(raw_.get(), path.c_str(), compression, quantize ? 1 : 0));
  }
  /// Finishes the cache being recorded.
  HairsysCacheSummary finish_recording() {
    HairsysCacheSummary s{};
    check(hairsys_session_finish_recording(raw_.get(), &s));
    return s;
  }
  /// The library's default child settings.
  static HairsysChildSettings default_child_settings() {
    HairsysChildSettings c{};
    check(hairsys_child_settings_default(&c));
    return c;
  }
  /// Render children of the current frame.
  Children children(const HairsysChildSettings& settings) const {
    HairsysChildren* raw = nullptr;
    check(hairsys_session_children(raw_.get(), &settings, &raw));
    return Children(raw);
  }
  /// The C handle, still owned by this object.
  HairsysSession* get() const noexcept { return raw_.get(); }

 private:
  explicit Session(HairsysSession* raw) : raw_(raw) {}
  std::unique_ptr<HairsysSession, detail::SessionDelete> raw_;
};

/// A finished cache, read back.
class Cache {
 public:
  explicit Cache(const std::string& path) {
    HairsysCache* raw = nullptr;
    check(hairsys_cache_open(path.c_str(), &raw));
    raw_.reset(raw);
  }
  HairsysCacheInfo info() const {
    HairsysCacheInfo i{};
    check(hairsys_cache_info(raw_.get(), &i));
    return i;
  }
  std::span<const uint32_t> strand_offsets() const {
    HairsysIndexView v{};
    check(hairsys_cache_strand_offsets(raw_.get(), &v));
    return {v.data, v.count};
  }
  /// Copies frame `frame` into `positions` (and `velocities` unless empty), xyz interleaved.
  void read_frame(uint32_t frame, std::span<float> positions, std::span<float> velocities = {}) {
    const size_t n = points_in(positions, "positions");
    if (!velocities.empty() && velocities.size() != positions.size()) {
      throw Error(HAIRSYS_STATUS_BAD_LENGTH,
                  "velocities: give as many floats as positions, or an empty span");
    }
    check(hairsys_cache_read_frame(raw_.get(), frame, positions.data(),
                                   velocities.empty() ? nullptr : velocities.data(), n));
  }

 private:
  std::unique_ptr<HairsysCache, detail::CacheDelete> raw_;
};

/// Writes the cache at `cache_path` as one animated USD file at `usd_path` (.usda or .usdc).
inline void export_usd(const std::string& cache_path, const std::string& usd_path) {
  check(hairsys_export_usd(cache_path.c_str(), usd_path.c_str()));
}

}  // namespace hairsys

#endif  // HAIRSYS_HPP
