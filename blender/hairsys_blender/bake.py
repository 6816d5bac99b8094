"""Baking: hand hairsys the evaluated (deformed) surface every frame, write an MCAP cache.

`Baker` does the work one frame at a time, so the modal operator (Esc cancels, progress in the
window manager) and a blocking bake (background mode, tests) share it. Everything handed to
hairsys is in world space, meters, Z up (Blender's convention): the surface's evaluated mesh
(armature, shape keys, any modifier) times its `matrix_world`, the curves' points times the
hair object's `matrix_world`; the scalp matrix stays the identity, so the surface may deform
and scale freely. Mesh colliders deform too: each frame a collider object's matrix is split into
its rigid part `R` (rotation and translation, the collider's pose, so a turning object turns
within the frame instead of cutting its corners) and the rest `R^-1 M` (scale, shear), which is
applied with the evaluated mesh (armature, shape keys, any modifier that keeps the vertex count)
to give the body-space vertices handed to `Session.set_collider_vertices`; within a frame each
vertex moves in a straight line and friction acts against that motion. Painted maps (goal
weights, stiffness, pins from vertex groups or curve attributes) are sampled at the first frame
by `maps.strand_maps`.
"""

import hashlib

import numpy as np

import hairsys

from .maps import strand_maps


def world_points(matrix, local):
    """(N, 3) points `local` transformed by the 4x4 `matrix` (a `mathutils.Matrix`)."""
    m = np.array(matrix, dtype=np.float64)
    return local @ m[:3, :3].T + m[:3, 3]


def rigid_part(matrix):
    """The rigid part of the 4x4 `matrix`: rotation (the orthogonal polar factor of its 3x3, so
    scale and shear are left out) and translation, as a 4x4 float64 array."""
    m = np.array(matrix, dtype=np.float64)
    u, _, vt = np.linalg.svd(m[:3, :3])
    if np.linalg.det(u @ vt) < 0:  # a mirroring matrix: keep a proper rotation
        u[:, -1] *= -1
    pose = np.eye(4)
    pose[:3, :3] = u @ vt
    pose[:3, 3] = m[:3, 3]
    return pose


def evaluated_mesh(obj, depsgraph, triangles=False, matrix=None):
    """The evaluated (deformed) mesh of `obj`: vertices (V, 3) float64 transformed by `matrix`
    (default: its world matrix) and, when asked, triangles (T, 3) int32."""
    ev = obj.evaluated_get(depsgraph)
    mesh = ev.to_mesh()
    try:
        co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
        mesh.vertices.foreach_get("co", co)
        m = ev.matrix_world if matrix is None else matrix
        verts = world_points(m, co.reshape(-1, 3).astype(np.float64))
        tris = None
        if triangles:
            mesh.calc_loop_triangles()
            tris = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
            mesh.loop_triangles.foreach_get("vertices", tris)
            tris = tris.reshape(-1, 3)
        return verts, tris
    finally:
        ev.to_mesh_clear()


#: Point attribute keeping the groom's own positions (object space) once playback overwrites
#: `position`; bakes start from it, and "Restore Groom" puts it back.
REST_ATTRIBUTE = "hairsys_rest"
#: Custom property of the Curves data: a digest of the positions playback wrote last. Positions
#: with another digest are not a cached frame but the groom (edited, combed, sculpted, restored).
PLAYED_KEY = "hairsys_played"


def digest(local):
    """A digest of object-space positions (float32 bytes): tells playback's frames from edits."""
    return hashlib.sha1(np.ascontiguousarray(local, dtype=np.float32).tobytes()).hexdigest()


def rest_positions(hair_obj):
    """The groom's rest positions (object space, (P, 3) float32), kept in the `REST_ATTRIBUTE`
    point attribute. The curves' `position` is the groom unless it is the frame playback wrote
    last (`PLAYED_KEY`): then the groom is the stored attribute; otherwise `position` is taken
    as the groom and stored, so an edit after a bake (or after Restore Groom) is what the next
    bake simulates."""
    curves = hair_obj.data
    n = len(curves.points)
    local = np.empty(n * 3, dtype=np.float32)
    curves.attributes["position"].data.foreach_get("vector", local)
    rest = curves.attributes.get(REST_ATTRIBUTE)
    if rest is not None and (rest.domain != "POINT" or len(rest.data) != n):
        curves.attributes.remove(rest)
        rest = None
    if rest is not None and curves.get(PLAYED_KEY) == digest(local):
        rest.data.foreach_get("vector", local)
        return local.reshape(-1, 3)
    if rest is None:
        rest = curves.attributes.new(REST_ATTRIBUTE, "FLOAT_VECTOR", "POINT")
    rest.data.foreach_set("vector", local)
    if PLAYED_KEY in curves:
        del curves[PLAYED_KEY]
    return local.reshape(-1, 3)


def curve_arrays(hair_obj):
    """The hair object's groom: world-space rest points (P, 3) and points per curve (C,)."""
    curves = hair_obj.data
    local = rest_positions(hair_obj)
    offsets = np.empty(len(curves.curves) + 1, dtype=np.int32)
    curves.curve_offset_data.foreach_get("value", offsets)
    return world_points(hair_obj.matrix_world, local.astype(np.float64)), np.diff(offsets)


def collider_objects(settings):
    """The mesh objects of the collider collection (empty without one)."""
    coll = settings.collider_collection
    if coll is None:
        return []
    return [o for o in coll.all_objects if o.type == "MESH"]


def collider_state(obj, depsgraph, triangles=False):
    """A collider object now: its pose (the rigid part of its world matrix, 4x4), its evaluated
    mesh's vertices in the pose's body space (V, 3) and, when asked, its triangles (T, 3)."""
    pose = rigid_part(obj.matrix_world)
    body = np.linalg.inv(pose) @ np.array(obj.matrix_world, dtype=np.float64)
    verts, tris = evaluated_mesh(obj, depsgraph, triangles=triangles, matrix=body)
    return pose, verts, tris


def expected_motion(context, colliders, first, last, fps):
    """How fast the colliders will move, as `Session.from_groom`'s `collider_speed` (m/s): per
    frame and collider, from its world matrix the translation plus the turn angle times the
    collider's reach from its origin, plus the fastest vertex of its evaluated mesh in body space
    (an armature, shape keys), so hairsys chooses its integrator as it would for a scene file
    with the same motion. Leaves the scene at `first`."""
    scene = context.scene
    speed = 0.0
    if colliders and last > first:
        previous = None
        for frame in range(first, last + 1):
            scene.frame_set(frame)
            depsgraph = context.evaluated_depsgraph_get()
            states = [collider_state(o, depsgraph)[:2] for o in colliders]
            if previous is not None:
                for (a, va), (b, vb) in zip(previous, states):
                    reach = float(np.linalg.norm(vb, axis=1).max()) if len(vb) else 0.0
                    moved = np.linalg.norm(b[:3, 3] - a[:3, 3])
                    turn = a[:3, :3].T @ b[:3, :3]
                    angle = np.arccos(np.clip((np.trace(turn) - 1.0) / 2.0, -1.0, 1.0))
                    deformed = (float(np.linalg.norm(vb - va, axis=1).max())
                                if len(vb) == len(va) and len(vb) else 0.0)
                    speed = max(speed, (moved + angle * reach + deformed) * fps)
            previous = states
        scene.frame_set(first)
    return dict(collider_speed=speed)


class Baker:
    """Bakes `hair_obj` over the scene's frame range into its cache (`playback.cache_file`),
    frame by frame (`step()` until it returns False), then `finish()`. `notes` are what the
    artist should know about the bake (where an unsaved file's cache went, a setting that could
    not apply); errors raise ValueError in the panel's words (`errors.explain`)."""

    def __init__(self, context, hair_obj):
        import os

        from . import errors
        from .playback import cache_file

        self.scene = context.scene
        self.hair = hair_obj
        self.settings = hair_obj.hairsys
        #: Messages for the artist (the operator reports them as warnings).
        self.notes = []
        surface = hair_obj.data.surface
        if surface is None or surface.type != "MESH":
            raise ValueError(f"{hair_obj.name!r} has no surface mesh: pick the mesh the hair "
                             "grows on as Surface in Properties › Object Data (the Curves' "
                             "data tab) › Surface")
        self.surface = surface
        s = self.settings
        self.path, note = cache_file(hair_obj)
        if note:
            self.notes.append(note)
        os.makedirs(os.path.dirname(self.path) or ".", exist_ok=True)
        self.first = self.scene.frame_start
        self.last = self.scene.frame_end
        #: The frame to go back to when the bake ends.
        self.start_frame = self.scene.frame_current
        self.scene.frame_set(self.first)
        depsgraph = context.evaluated_depsgraph_get()
        verts, tris = evaluated_mesh(surface, depsgraph, triangles=True)
        points, counts = curve_arrays(hair_obj)
        maps = strand_maps(hair_obj, s, verts, tris, points, counts)
        self.colliders = collider_objects(s)
        specs = []
        self.collider_counts = []
        for obj in self.colliders:
            pose, cv, ct = collider_state(obj, depsgraph, triangles=True)
            specs.append({"shape": "mesh", "vertices": cv, "triangles": ct, "matrix": pose,
                          "thickness": s.collider_thickness, "friction": s.collider_friction})
            self.collider_counts.append(len(cv))
        fps = self.scene.render.fps / self.scene.render.fps_base
        motion = expected_motion(context, self.colliders, self.first, self.last, fps)
        sag_free = s.sag_free
        if sag_free and maps.get("strand_scales"):
            sag_free = False
            self.notes.append(
                "Sag-Free Rest is skipped: it solves rest shapes for one material, and the "
                "Stiffness, Stretch, Damping or Drag map gives strands their own (set those maps "
                "to None to hold the groom's shape, or turn Sag-Free Rest off)")
        if s.goal_stiffness > 0 and s.weight_source == "NONE":
            self.notes.append(
                f"Goal Stiffness is {s.goal_stiffness:g} N/m but Goal Weights is None, so no "
                "point has a goal spring: pick a vertex group or curve attribute as Goal Weights")
        options = dict(
            fps=fps, first_frame=self.first, substeps=s.substeps if s.substeps > 0 else "auto",
            gravity=tuple(self.scene.gravity) if self.scene.use_gravity else (0.0, 0.0, 0.0),
            stretch_stiffness=s.stretch_stiffness, max_strain=s.max_stretch,
            bend_stiffness=s.bend_stiffness,
            goal_stiffness=s.goal_stiffness, air_drag=s.air_drag,
            mass_per_length=s.mass_per_length, radius=s.radius,
            max_snap_distance=s.max_snap_distance, sag_free=sag_free,
            scalp_collider=s.surface_collision, scalp_thickness=s.surface_thickness,
            scalp_friction=s.surface_friction, colliders=specs, **motion,
        )
        if s.threads > 0:
            options["threads"] = s.threads
        options.update(maps)
        try:
            self.session = hairsys.Session.from_groom(verts, tris, points, counts, **options)
        except ValueError as e:
            raise ValueError(errors.explain(e, hair_obj, points, counts, verts, tris)) from None
        self.session.write_cache(self.path)
        self.frame = self.first
        #: The last frame's report (`Session.step`'s dict), None before the first step.
        self.report = None

    @property
    def progress(self):
        """Fraction of the frames baked, 0-1."""
        return (self.frame - self.first) / max(1, self.last - self.first)

    def step(self, context):
        """Bakes the next frame; False when every frame is baked."""
        if self.frame >= self.last:
            return False
        self.frame += 1
        self.scene.frame_set(self.frame)
        depsgraph = context.evaluated_depsgraph_get()
        verts, _ = evaluated_mesh(self.surface, depsgraph)
        for i, (obj, count) in enumerate(zip(self.colliders, self.collider_counts)):
            pose, cv, _ = collider_state(obj, depsgraph)
            if len(cv) != count:
                raise ValueError(
                    f"collider {obj.name!r} has {len(cv)} vertices at frame {self.frame} but "
                    f"{count} at frame {self.first}: a collider's modifiers must keep its vertex "
                    "count (remove or apply the modifier that changes it)")
            self.session.set_collider_pose(i, pose)
            self.session.set_collider_vertices(i, cv)
        self.report = self.session.step(scalp_vertices=verts)
        return True

    def finish(self):
        """Finishes the cache (also after a cancel: the frames baked so far are kept)."""
        return self.session.finish_cache()
