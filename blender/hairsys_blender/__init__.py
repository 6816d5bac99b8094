"""hairsys for Blender: bake hair Curves on their (deforming) surface mesh with hairsys and play
the MCAP cache back.

Select a hair Curves object whose Surface is a mesh, open Properties > Physics > hairsys, set
the cache path and the parameters, press Bake (progress in the status bar, Esc cancels and keeps
the frames baked so far). With Playback on, the curves take the cache's positions whenever the
frame changes. Every frame of a bake hands hairsys the evaluated surface (armature, shape keys,
any modifier) in world space and the poses of the collider collection's meshes. Goal weights,
pins and per-strand factors of the bend and stretch stiffness, stretch damping and air drag may
be painted: each takes a surface vertex group or a curve attribute (`maps`).
"""

import bpy
import numpy as np
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty,
                       StringProperty)

from . import children, playback, widths
from .bake import PLAYED_KEY, REST_ATTRIBUTE
from .maps import PURPOSES


def map_sources(none):
    """The sources of a painted map (see `maps`); `none` describes the NONE choice."""
    return [("NONE", "None", none),
            ("ATTRIBUTE", "Curve Attribute",
             "A float attribute of the curves (point or curve domain)"),
            ("VERTEX_GROUP", "Vertex Group",
             "A vertex group of the surface, blended at each curve's root over its triangle")]


def on_children_setting(settings, context):
    """Update callback of every children setting: regenerates the children of its object."""
    children_changed(settings.id_data, context)


class HairsysSettings(bpy.types.PropertyGroup):
    """hairsys settings of a hair Curves object."""

    cache_path: StringProperty(
        name="Cache", subtype="FILE_PATH", default="//hair.mcap",
        options={"PATH_SUPPORTS_BLEND_RELATIVE"},
        description="MCAP cache the bake writes and playback reads (// = next to the .blend; "
                    "a .blend never saved puts it in the temporary directory); missing folders "
                    "are created")
    playback: BoolProperty(
        name="Playback", default=True,
        description="Set the curves from the cache whenever the frame changes")
    substeps: IntProperty(
        name="Substeps", default=0, min=0, max=100000,
        description="Force substeps per frame; 0 = chosen by hairsys (the stability bound of "
                    "semi-implicit Euler, or BDF2's accuracy limit)")
    threads: IntProperty(
        name="Threads", default=0, min=0, max=256,
        description="Threads of the bake; 0 = all cores")
    stretch_stiffness: FloatProperty(
        name="Stretch Stiffness", default=40.0, min=0.0, unit="NONE",
        description="Springs between neighbouring points, N/m")
    max_stretch: FloatProperty(
        name="Max Stretch", default=0.01, min=0.0, max=10.0, soft_max=0.2, precision=3,
        description="Strain limit: after every substep no segment is longer than (1 + this) "
                    "times its groomed length (0.01 = 1 %; 0 = inextensible)")
    bend_stiffness: FloatProperty(
        name="Bend Stiffness", default=0.5, min=0.0,
        description="Springs towards the rest direction, N/m")
    goal_stiffness: FloatProperty(
        name="Goal Stiffness", default=0.0, min=0.0,
        description="Springs towards the animated rest shape, N/m, times each point's goal weight")
    sag_free: BoolProperty(
        name="Sag-Free Rest", default=True,
        description="Solve rest shapes so that the groom as combed is at rest under gravity at "
                    "the first frame: hair keeps its shape instead of sagging when the "
                    "simulation starts (one material: skipped with a Stiffness, Stretch, "
                    "Damping or Drag map)")
    air_drag: FloatProperty(
        name="Air Drag", default=2.0, min=0.0,
        description="Decay rate of velocity in still air, 1/s")
    mass_per_length: FloatProperty(
        name="Mass per Length", default=0.001, min=1e-9, precision=5,
        description="Linear density of a strand, kg/m")
    radius: FloatProperty(
        name="Radius", default=0.001, min=0.0, unit="LENGTH", precision=4,
        description="Strand (wisp) radius: its collision sphere")
    max_snap_distance: FloatProperty(
        name="Max Snap Distance", default=0.025, min=0.0, unit="LENGTH",
        description="Largest distance a curve's root may lie from the surface")
    weight_source: EnumProperty(
        name="Goal Weights", default="NONE",
        items=map_sources("No goal springs (weights 0)"),
        description="Where the per-point goal weights come from, 0-1 (times Goal Stiffness)")
    weight_name: StringProperty(
        name="Weight Name", default="goal",
        description="Name of the curve attribute or surface vertex group holding the goal weights")
    stiffness_source: EnumProperty(
        name="Stiffness", default="NONE",
        items=map_sources("Every strand has the panel's Bend Stiffness"),
        description="Where each strand's bend stiffness factor comes from (≥ 0; 1 = the panel's "
                    "Bend Stiffness, 0 = none)")
    stiffness_name: StringProperty(
        name="Stiffness Name", default="stiffness",
        description="Name of the curve attribute or surface vertex group holding the factors")
    stretch_source: EnumProperty(
        name="Stretch", default="NONE",
        items=map_sources("Every strand has the panel's Stretch Stiffness"),
        description="Where each strand's stretch stiffness factor comes from (≥ 0; 1 = the "
                    "panel's Stretch Stiffness)")
    stretch_name: StringProperty(
        name="Stretch Name", default="stretch",
        description="Name of the curve attribute or surface vertex group holding the factors")
    damping_source: EnumProperty(
        name="Damping", default="NONE",
        items=map_sources("Every strand has hairsys's stretch damping"),
        description="Where each strand's stretch damping factor comes from (≥ 0; 1 = hairsys's "
                    "stretch damping, 0 = none)")
    damping_name: StringProperty(
        name="Damping Name", default="damping",
        description="Name of the curve attribute or surface vertex group holding the factors")
    drag_source: EnumProperty(
        name="Drag", default="NONE",
        items=map_sources("Every strand has the panel's Air Drag"),
        description="Where each strand's air drag factor comes from (≥ 0; 1 = the panel's Air "
                    "Drag, 0 = none)")
    drag_name: StringProperty(
        name="Drag Name", default="drag",
        description="Name of the curve attribute or surface vertex group holding the factors")
    pin_source: EnumProperty(
        name="Pin", default="NONE",
        items=map_sources("Only the roots are pinned"),
        description="Where pins come from: points whose value is ≥ 0.5 are held on the groom's "
                    "shape and follow the surface rigidly (a vertex group pins whole strands)")
    pin_name: StringProperty(
        name="Pin Name", default="pin",
        description="Name of the curve attribute or surface vertex group holding the pins")
    surface_collision: BoolProperty(
        name="Surface Collision", default=True,
        description="Hair collides with its surface mesh, as evaluated (deformed) at every frame")
    surface_thickness: FloatProperty(
        name="Surface Thickness", default=0.002, min=0.0, unit="LENGTH",
        description="Distance kept between hair and the surface, on top of the strand radius")
    surface_friction: FloatProperty(
        name="Surface Friction", default=0.3, min=0.0,
        description="Coulomb friction coefficient between hair and the surface")
    collider_collection: PointerProperty(
        name="Colliders", type=bpy.types.Collection,
        description="Mesh objects hair collides with, as evaluated (moved, deformed) at every "
                    "frame; their modifiers must keep the vertex count")
    collider_thickness: FloatProperty(
        name="Collider Thickness", default=0.002, min=0.0, unit="LENGTH",
        description="Distance kept between hair and the colliders")
    collider_friction: FloatProperty(
        name="Collider Friction", default=0.3, min=0.0,
        description="Coulomb friction coefficient between hair and the colliders")
    root_width: FloatProperty(
        name="Root Width", default=80e-6, min=0.0, max=1.0, unit="LENGTH", precision=6,
        update=lambda self, context: widths.update(self.id_data),
        description="Hair width (diameter) at the root, for renders: the curves' radius "
                    "attribute is half the width, tapered from root to tip")
    tip_width: FloatProperty(
        name="Tip Width", default=20e-6, min=0.0, max=1.0, unit="LENGTH", precision=6,
        update=lambda self, context: widths.update(self.id_data),
        description="Hair width (diameter) at the tip, for renders")
    children_type: EnumProperty(
        name="Children", default="NONE",
        items=[("NONE", "None", "No children"),
               ("SIMPLE", "Simple", "Children rooted in a disc around each guide, following it"),
               ("INTERPOLATED", "Interpolated",
                "Children rooted between guides, blending their neighbouring guides")],
        update=on_children_setting,
        description="Render children generated around the guides at every frame, into a "
                    "second Curves object that renders")
    child_display_amount: IntProperty(
        name="Display Amount", default=10, min=1, max=100000,
        update=on_children_setting,
        description="Children per guide in the viewport (the first of the rendered ones)")
    child_render_amount: IntProperty(
        name="Render Amount", default=100, min=1, max=100000,
        update=on_children_setting,
        description="Children per guide in renders")
    child_radius: FloatProperty(
        name="Spread", default=0.005, min=0.0, unit="LENGTH",
        update=on_children_setting,
        description="Radius of the disc around a guide's root that its simple children grow in")
    child_clump: FloatProperty(
        name="Clump", default=0.0, min=-1.0, max=1.0, subtype="FACTOR",
        update=on_children_setting,
        description="How far tips are drawn to their guide: 1 onto it, 0 none, -1 apart")
    child_curl_radius: FloatProperty(
        name="Curl Radius", default=0.0, min=0.0, unit="LENGTH",
        update=on_children_setting,
        description="Radius of the children's helical curl around their path")
    child_curl_frequency: FloatProperty(
        name="Curl Frequency", default=0.0, min=0.0,
        update=on_children_setting,
        description="Turns of the curl per meter of hair")
    child_roughness: FloatProperty(
        name="Roughness", default=0.0, min=0.0, unit="LENGTH",
        update=on_children_setting,
        description="Amplitude of the uniform noise that roughens each child")
    child_roughness_endpoint: FloatProperty(
        name="Endpoint Roughness", default=0.0, min=0.0, unit="LENGTH",
        update=on_children_setting,
        description="Noise amplitude at the tips, growing from the root")
    child_length_variation: FloatProperty(
        name="Length Variation", default=0.0, min=0.0, max=0.99, subtype="FACTOR",
        update=on_children_setting,
        description="Random shortening of each child, as a fraction of its length")
    child_subdivisions: IntProperty(
        name="Render Steps", default=4, min=1, max=64,
        update=on_children_setting,
        description="Smooth pieces per guide segment in renders (the viewport shows the "
                    "guides' own points)")
    child_seed: IntProperty(
        name="Seed", default=0, min=0,
        update=on_children_setting,
        description="Another seed gives other children")
    children_object: PointerProperty(
        name="Children Object", type=bpy.types.Object,
        poll=lambda self, obj: obj.type == "CURVES",
        description="The Curves object the children are written to (made on first use)")


def children_changed(obj, context):
    """Regenerates `obj`'s children after a children setting changed."""
    if obj.hairsys.children_type == "NONE":
        return
    try:
        children.update(obj, context.evaluated_depsgraph_get())
    except (ValueError, OSError) as e:
        print(f"hairsys: cannot make the children of {obj.name}: {e}")


def hair_object(context):
    obj = context.object
    return obj if obj is not None and obj.type == "CURVES" else None


class HAIRSYS_OT_bake(bpy.types.Operator):
    """Simulate the hair over the scene's frame range on the evaluated surface and write the cache"""

    bl_idname = "hairsys.bake"
    bl_label = "Bake Hair"
    bl_options = {"REGISTER"}

    _baker = None
    _timer = None

    @classmethod
    def poll(cls, context):
        return hair_object(context) is not None

    def _start(self, context):
        from .bake import Baker

        playback.baking = True
        try:
            obj = hair_object(context)
            playback.forget(playback.cache_file(obj)[0])
            self._baker = Baker(context, obj)
        except (ValueError, OSError) as e:
            playback.baking = False
            self.report({"ERROR"}, f"hairsys: {e}")
            return False
        for note in self._baker.notes:
            self.report({"WARNING"}, f"hairsys: {note}")
        return True

    def _end(self, context, cancelled):
        playback.baking = False
        summary = self._baker.finish()
        widths.update(self._baker.hair)
        frame = self._baker.frame
        start = self._baker.start_frame
        self._baker = None
        context.scene.frame_set(start)
        word = "cancelled after" if cancelled else "baked"
        self.report({"WARNING" if cancelled else "INFO"},
                    f"hairsys: {word} frame {frame}: {summary['frames']} frames in {summary['path']}")

    def execute(self, context):
        """Blocking bake (scripts, background mode)."""
        if not self._start(context):
            return {"CANCELLED"}
        try:
            while self._baker.step(context):
                pass
        except (ValueError, RuntimeError, OSError) as e:
            self.report({"ERROR"}, f"hairsys: frame {self._baker.frame}: {e}")
            self._end(context, cancelled=True)
            return {"CANCELLED"}
        self._end(context, cancelled=False)
        return {"FINISHED"}

    def invoke(self, context, event):
        if not self._start(context):
            return {"CANCELLED"}
        wm = context.window_manager
        wm.progress_begin(0, 100)
        self._timer = wm.event_timer_add(0.0001, window=context.window)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        wm = context.window_manager
        if event.type == "ESC":
            self._stop(context, cancelled=True)
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        try:
            more = self._baker.step(context)
        except (ValueError, RuntimeError, OSError) as e:
            self.report({"ERROR"}, f"hairsys: frame {self._baker.frame}: {e}")
            self._stop(context, cancelled=True)
            return {"CANCELLED"}
        wm.progress_update(int(100 * self._baker.progress))
        context.workspace.status_text_set(
            f"hairsys: frame {self._baker.frame} of {self._baker.last} (Esc to cancel)")
        if more:
            return {"RUNNING_MODAL"}
        self._stop(context, cancelled=False)
        return {"FINISHED"}

    def _stop(self, context, cancelled):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        self._end(context, cancelled)


class HAIRSYS_OT_play_frame(bpy.types.Operator):
    """Set the hair from the cache at the current frame"""

    bl_idname = "hairsys.play_frame"
    bl_label = "Load Cached Frame"

    @classmethod
    def poll(cls, context):
        return hair_object(context) is not None

    def execute(self, context):
        obj = hair_object(context)
        try:
            ok = playback.apply_frame(obj, context.scene.frame_current)
        except (OSError, ValueError) as e:
            self.report({"ERROR"}, f"hairsys: {e}")
            return {"CANCELLED"}
        if not ok:
            self.report({"WARNING"}, "hairsys: the cache has no such frame (or other curves)")
            return {"CANCELLED"}
        return {"FINISHED"}


class HAIRSYS_OT_restore_groom(bpy.types.Operator):
    """Put the groom's own curve positions back (playback replaced them) and stop playback"""

    bl_idname = "hairsys.restore_groom"
    bl_label = "Restore Groom"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = hair_object(context)
        return obj is not None and REST_ATTRIBUTE in obj.data.attributes

    def execute(self, context):
        obj = hair_object(context)
        rest = obj.data.attributes[REST_ATTRIBUTE]
        buf = np.empty(len(rest.data) * 3, dtype=np.float32)
        rest.data.foreach_get("vector", buf)
        obj.data.attributes["position"].data.foreach_set("vector", buf)
        if PLAYED_KEY in obj.data:
            del obj.data[PLAYED_KEY]
        obj.data.update_tag()
        obj.hairsys.playback = False
        return {"FINISHED"}


class HAIRSYS_OT_update_children(bpy.types.Operator):
    """Generate the render children of the hair as it is now into the children object"""

    bl_idname = "hairsys.update_children"
    bl_label = "Update Children"
    bl_options = {"REGISTER", "UNDO"}

    render: BoolProperty(name="Render Level", default=False,
                         description="Every render child instead of the viewport's amount")

    @classmethod
    def poll(cls, context):
        obj = hair_object(context)
        return obj is not None and obj.hairsys.children_type != "NONE"

    def execute(self, context):
        obj = hair_object(context)
        try:
            made = children.update(obj, context.evaluated_depsgraph_get(), render=self.render)
        except (ValueError, OSError) as e:
            self.report({"ERROR"}, f"hairsys: {e}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"hairsys: {len(made.data.curves)} children in {made.name!r}")
        return {"FINISHED"}


class HAIRSYS_PT_panel(bpy.types.Panel):
    bl_label = "hairsys"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "physics"

    @classmethod
    def poll(cls, context):
        return hair_object(context) is not None

    def draw(self, context):
        s = context.object.hairsys
        col = self.layout.column()
        col.prop(s, "cache_path")
        row = col.row()
        row.operator(HAIRSYS_OT_bake.bl_idname, icon="PHYSICS")
        row.prop(s, "playback")
        col.operator(HAIRSYS_OT_restore_groom.bl_idname)
        col.separator()
        for name in ("stretch_stiffness", "max_stretch", "bend_stiffness", "goal_stiffness",
                     "sag_free", "air_drag", "mass_per_length", "radius", "substeps", "threads",
                     "max_snap_distance"):
            col.prop(s, name)
        col.separator()
        for _, source, name, _ in PURPOSES:
            col.prop(s, source)
            if getattr(s, source) != "NONE":
                col.prop(s, name)
        if s.goal_stiffness > 0 and s.weight_source == "NONE":
            col.label(text="Goal Stiffness acts only where Goal Weights are painted",
                      icon="ERROR")
        col.separator()
        col.prop(s, "surface_collision")
        if s.surface_collision:
            col.prop(s, "surface_thickness")
            col.prop(s, "surface_friction")
        col.prop(s, "collider_collection")
        if s.collider_collection is not None:
            col.prop(s, "collider_thickness")
            col.prop(s, "collider_friction")
        col.separator()
        col.label(text="Render")
        col.prop(s, "root_width")
        col.prop(s, "tip_width")
        col.prop(s, "children_type")
        if s.children_type != "NONE":
            for name in ("child_display_amount", "child_render_amount", "child_radius",
                         "child_clump", "child_curl_radius", "child_curl_frequency",
                         "child_roughness", "child_roughness_endpoint",
                         "child_length_variation", "child_subdivisions", "child_seed",
                         "children_object"):
                if name == "child_radius" and s.children_type == "INTERPOLATED":
                    continue
                col.prop(s, name)
            col.operator(HAIRSYS_OT_update_children.bl_idname)


CLASSES = (HairsysSettings, HAIRSYS_OT_bake, HAIRSYS_OT_play_frame, HAIRSYS_OT_restore_groom,
           HAIRSYS_OT_update_children, HAIRSYS_PT_panel)
#: (handler list name, handler) pairs the add-on adds.
HANDLERS = (("frame_change_post", playback.on_frame_change),
            ("render_init", playback.on_render_init),
            ("render_pre", playback.on_render_pre),
            ("render_complete", playback.on_render_end),
            ("render_cancel", playback.on_render_end))


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Object.hairsys = PointerProperty(type=HairsysSettings)
    for name, handler in HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        if handler not in handlers:
            handlers.append(handler)


def unregister():
    for name, handler in HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        if handler in handlers:
            handlers.remove(handler)
    children.forget()
    del bpy.types.Object.hairsys
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
