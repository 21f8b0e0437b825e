# restitch for Blender: resize a mesh object along its repeats (shelves, fences, railings), live.
#
# 3D View > Sidebar > restitch. "Analyse" finds the active mesh object's repeats (drawn as arrows from its
# origin); a slider per principal offset adds or removes whole repeats, live; a size field gives the nearest
# whole repeats, scaled to the size exactly when "exact" is on; the pivot says what stays put. The result
# replaces the object's mesh data (one undo step per committed change), keeping every material slot, UV
# map and, where the mesh had them, custom normals, and the object's transform. The original mesh is kept
# (Object.restitch_original): "Original" puts it back, "Apply" keeps the result for good.
#
# Operators: bpy.ops.object.restitch_analyze(), bpy.ops.object.restitch_resize(steps=(a, b, c), size=(x,
# y, z), exact=False, pivot='origin'), bpy.ops.object.restitch_promote(index=i),
# bpy.ops.object.restitch_restore(), bpy.ops.object.restitch_apply().
#
# The work is done by the restitch Python module (the .so beside this file, built for Blender's Python by
# scripts/pack-blender.sh). A mesh goes to restitch in the object's local space: one vertex per distinct
# (vertex, split normal, UVs) corner of its triangles, UVs with v flipped to glTF's convention, a material
# per triangle; the result comes back with the vertices at one position merged, so only UV and normal
# seams stay split, as Blender keeps them per corner. Analysis results are cached per original mesh, so a
# slider move costs one resize.
bl_info = {
    "name": "restitch",
    "author": "The restitch authors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > restitch",
    "description": "Resize man-made models along their repeats by graph-cut stitching",
    "category": "Object",
}

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatVectorProperty, IntVectorProperty, PointerProperty
from mathutils import Vector

from . import restitch as rs

PIVOTS = [(p, p, f"keep the {p} of the model in place") for p in ("origin", "min", "center", "max")] + [
    ("cursor", "3D cursor", "keep what lies at the 3D cursor in place")]

# Per original mesh (its name and pointer) and shift (the 3D cursor in local space for the cursor pivot, else
# None): the restitch mesh, the analysis, a Retargeter, the layers.
_cache = {}
_draw_handle = None


def _key(me, shift=None):
    return (me.name, me.as_pointer(), shift)


def _original(obj):
    return obj.restitch_original if obj.restitch_original is not None else obj.data


def mesh_to_restitch(me, shift=None):
    """The mesh as a restitch.Mesh in local space (less `shift`), and what is needed to rebuild a Blender mesh."""
    me.calc_loop_triangles()
    me.calc_normals_split()
    nl, nv, nt = len(me.loops), len(me.vertices), len(me.loop_triangles)
    if nt == 0:
        raise rs.Error("the mesh has no faces")
    co = np.empty(3 * nv, np.float32)
    me.vertices.foreach_get("co", co)
    vert = np.empty(nl, np.int64)
    me.loops.foreach_get("vertex_index", vert)
    nor = np.empty(3 * nl, np.float32)
    me.loops.foreach_get("normal", nor)
    uvs = []
    for layer in me.uv_layers:
        uv = np.empty(2 * nl, np.float32)
        layer.data.foreach_get("uv", uv)
        uv = uv.reshape(-1, 2)
        uvs.append(np.stack([uv[:, 0], 1.0 - uv[:, 1]], axis=1))  # glTF's v points down
    tri_loops = np.empty(3 * nt, np.int64)
    me.loop_triangles.foreach_get("loops", tri_loops)
    mat = np.empty(nt, np.int64)
    me.loop_triangles.foreach_get("material_index", mat)
    # One restitch vertex per distinct corner (vertex, normal, UVs).
    key = np.concatenate([vert[:, None].astype(np.float64), nor.reshape(-1, 3)] + uvs, axis=1)
    _, first, corner_vertex = np.unique(key, axis=0, return_index=True, return_inverse=True)
    corner_vertex = corner_vertex.ravel()
    positions = co.reshape(-1, 3)[vert[first]]
    if shift is not None:
        positions = positions - np.asarray(shift, np.float32)
    normals = nor.reshape(-1, 3)[first]
    mesh = rs.Mesh(positions, corner_vertex[tri_loops].reshape(-1, 3), normals=normals,
                   uvs=[uv[first] for uv in uvs], material_ids=mat)
    layers = {"uv": [layer.name for layer in me.uv_layers],
              "custom_normals": me.has_custom_normals,
              "smooth": any(p.use_smooth for p in me.polygons),
              "auto_smooth": (me.use_auto_smooth, me.auto_smooth_angle)}
    return mesh, layers


def restitch_to_mesh(result, template, layers, name, shift=None):
    """A new Blender mesh from a restitch.Mesh (plus `shift`), with the template's materials, UV maps, shading."""
    P, T = result.positions, result.triangles.astype(np.int64)
    if shift is not None:
        P = P + np.asarray(shift, np.float32)
    unique, inverse = np.unique(P, axis=0, return_inverse=True)  # one Blender vertex per position
    merged = inverse.ravel()[T]
    # A sliver whose corners share a position keeps corners of its own (Blender wants distinct corners).
    sliver = (merged[:, 0] == merged[:, 1]) | (merged[:, 1] == merged[:, 2]) | (merged[:, 0] == merged[:, 2])
    if sliver.any():
        corners = T[sliver].ravel()
        merged[sliver] = (len(unique) + np.arange(len(corners))).reshape(-1, 3)
        unique = np.concatenate([unique, P[corners]])
    loops = merged.ravel()
    me = bpy.data.meshes.new(name)
    me.vertices.add(len(unique))
    me.vertices.foreach_set("co", unique.astype(np.float32).ravel())
    me.loops.add(len(loops))
    me.loops.foreach_set("vertex_index", loops)
    me.polygons.add(len(T))
    me.polygons.foreach_set("loop_start", np.arange(0, len(loops), 3))
    me.polygons.foreach_set("loop_total", np.full(len(T), 3))
    me.polygons.foreach_set("material_index", np.maximum(result.material_ids, 0))
    for name_uv, uv in zip(layers["uv"], result.uvs):
        layer = me.uv_layers.new(name=name_uv)
        corner = uv[T.ravel()]
        layer.data.foreach_set("uv", np.stack([corner[:, 0], 1.0 - corner[:, 1]], axis=1).ravel())
    me.polygons.foreach_set("use_smooth", np.full(len(T), layers["smooth"]))
    for m in template.materials:
        me.materials.append(m)
    me.update(calc_edges=True)  # no validate(): it would drop the faces of double-sided walls restitch keeps
    me.use_auto_smooth, me.auto_smooth_angle = layers["auto_smooth"]
    if layers["custom_normals"] and result.normals is not None:
        me.use_auto_smooth = True
        me.normals_split_custom_set(result.normals[T.ravel()].tolist())
    return me


def analyse(obj, shift=None):
    original = _original(obj)
    mesh, layers = mesh_to_restitch(original, shift)
    analysis = rs.analyze(mesh)
    base = _cache.get(_key(original)) if shift is not None else None
    promoted = base["promoted"] if base else []
    if promoted:  # the cursor pivot's analysis follows the panel's promotions
        analysis = analysis.promote(promoted)
    entry = {"mesh": mesh, "layers": layers, "analysis": analysis, "promoted": promoted, "retargeter": None,
             "warnings": [], "report": None}
    _cache[_key(original, shift)] = entry
    return entry


def cached(obj, shift=None):
    return _cache.get(_key(_original(obj), shift))


def _cursor_shift(obj):
    c = obj.matrix_world.inverted() @ bpy.context.scene.cursor.location
    return (round(c.x, 9), round(c.y, 9), round(c.z, 9))


def retargeter(entry, pivot):
    if entry["retargeter"] is None or entry.get("pivot") != pivot:
        entry["retargeter"] = rs.Retargeter(entry["mesh"], entry["analysis"], pivot=pivot)
        entry["pivot"] = pivot
    return entry["retargeter"]


def resize(obj, steps=None, size=None, exact=False, pivot="origin"):
    """Resizes obj (its original mesh) and puts the result in place of its mesh data; returns the report.
    The cursor pivot analyses the mesh moved so the cursor is its origin (once per cursor position), and
    keeps the origin: what lies at the cursor stays put."""
    shift = _cursor_shift(obj) if pivot == "cursor" else None
    entry = cached(obj, shift) or analyse(obj, shift)
    if not entry["analysis"].principal_offsets:
        raise rs.Error("no repeat found in this mesh: there is nothing to resize along")
    r = retargeter(entry, "origin" if shift is not None else pivot)
    n = len(entry["analysis"].principal_offsets)
    if size is not None:
        out = r.resize(size=tuple(size), exact=exact)
    else:
        out = r.resize(steps=list(steps)[:n])
    original = _original(obj)
    previous = obj.data
    if all(s == 0 for s in out.steps) and size is None:
        obj.data = original
    else:
        obj.data = restitch_to_mesh(out.mesh, original, entry["layers"], original.name + ".restitch", shift)
    if obj.restitch_original is None:
        original.use_fake_user = True  # kept while the object shows a result
        obj.restitch_original = original
    if previous is not original and previous.users == 0:
        bpy.data.meshes.remove(previous)
    for e in {id(entry): entry, id(cached(obj) or entry): cached(obj) or entry}.values():  # the panel's too
        e["report"] = out.report
        e["warnings"] = [w["message"] for w in out.warnings]
    return out.report


def _show_steps(obj, steps):
    """Sets the sliders without resizing: they follow a resize made another way."""
    obj["restitch_updating"] = True
    obj.restitch_steps = steps
    del obj["restitch_updating"]


def _forget_original(obj):
    """The object no longer refers to its original mesh; returns that mesh."""
    original = obj.restitch_original
    obj.restitch_original = None
    original.use_fake_user = False
    return original


def _pitch(obj, offset):
    return (obj.matrix_world.to_3x3() @ Vector(offset)).length


# ---- operators -------------------------------------------------------------------------------------------------------

class RestitchOperator:
    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"

    def fail(self, e):
        self.report({"ERROR"}, f"restitch: {e}")
        return {"CANCELLED"}


class OBJECT_OT_restitch_analyze(RestitchOperator, bpy.types.Operator):
    """Find how the active mesh repeats"""
    bl_idname = "object.restitch_analyze"
    bl_label = "Analyse repeats"
    bl_options = {"REGISTER"}

    def execute(self, context):
        obj = context.active_object
        try:
            entry = analyse(obj)
        except rs.Error as e:
            return self.fail(e)
        offsets = entry["analysis"].principal_offsets
        if not offsets:
            n = len(entry["analysis"].candidates)
            self.report({"WARNING"}, "restitch: no repeat found" +
                        (f"; {n} candidate(s) can be promoted" if n else ": nothing to resize along"))
        else:
            pitches = ", ".join(f"{_pitch(obj, v):.4g}" for v in offsets)
            self.report({"INFO"}, f"restitch: {len(offsets)} repeat(s), pitch {pitches}")
        obj.restitch_steps = (0, 0, 0)
        return {"FINISHED"}


class OBJECT_OT_restitch_resize(RestitchOperator, bpy.types.Operator):
    """Resize the active mesh along its repeats"""
    bl_idname = "object.restitch_resize"
    bl_label = "Resize"
    bl_options = {"REGISTER", "UNDO"}

    steps: IntVectorProperty(name="Steps", size=3, default=(0, 0, 0),
                             description="Whole repeats to add (negative: remove) along each principal offset")
    size: FloatVectorProperty(name="Size", size=3, default=(0.0, 0.0, 0.0), subtype="XYZ_LENGTH", unit="LENGTH",
                              description="A bounding-box size in the object's local units (0 keeps an axis); "
                                          "used instead of the steps when not all 0")
    exact: BoolProperty(name="Exact", default=False,
                        description="Scale the nearest whole repeats to the size exactly, about the pivot")
    pivot: EnumProperty(name="Pivot", items=PIVOTS, default="origin")

    def execute(self, context):
        obj = context.active_object
        use_size = any(v > 0 for v in self.size)
        try:
            report = resize(obj, steps=self.steps, size=self.size if use_size else None, exact=self.exact,
                            pivot=self.pivot)
        except rs.Error as e:
            return self.fail(e)
        _show_steps(obj, (list(report["steps_principal"]) + [0] * 3)[:3])
        warnings = cached(obj)["warnings"]
        if warnings:
            self.report({"WARNING"}, "restitch: " + "; ".join(warnings))
        return {"FINISHED"}


class OBJECT_OT_restitch_promote(RestitchOperator, bpy.types.Operator):
    """Make a candidate repeat a principal offset: a slider then moves along it"""
    bl_idname = "object.restitch_promote"
    bl_label = "Promote"
    bl_options = {"REGISTER"}

    index: bpy.props.IntProperty(name="Candidate", default=0, min=0)

    def execute(self, context):
        entry = cached(context.active_object)
        if entry is None:
            return self.fail("analyse the mesh first")
        candidates = entry["analysis"].candidates
        if self.index >= len(candidates):
            return self.fail(f"there are {len(candidates)} candidates")
        offset = tuple(candidates[self.index]["offset"])
        try:
            entry["analysis"] = entry["analysis"].promote([offset])
        except rs.Error as e:
            return self.fail(e)
        entry["promoted"] = [offset]
        entry["retargeter"] = None
        original = _original(context.active_object)
        for key in [k for k in _cache if k[:2] == _key(original)[:2] and k[2] is not None]:
            del _cache[key]  # cursor-pivot analyses: made again with the promotion
        return {"FINISHED"}


class OBJECT_OT_restitch_restore(RestitchOperator, bpy.types.Operator):
    """Put the original mesh back"""
    bl_idname = "object.restitch_restore"
    bl_label = "Original"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        obj = context.active_object
        if obj.restitch_original is None:
            return {"CANCELLED"}
        shown = obj.data
        obj.data = _forget_original(obj)
        if shown is not obj.data and shown.users == 0:
            bpy.data.meshes.remove(shown)
        _show_steps(obj, (0, 0, 0))
        return {"FINISHED"}


class OBJECT_OT_restitch_apply(RestitchOperator, bpy.types.Operator):
    """Keep the result: forget the original mesh"""
    bl_idname = "object.restitch_apply"
    bl_label = "Apply"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        obj = context.active_object
        if obj.restitch_original is None:
            return {"CANCELLED"}
        original = _forget_original(obj)
        for key in [k for k in _cache if k[:2] == _key(original)[:2]]:
            del _cache[key]
        _show_steps(obj, (0, 0, 0))
        return {"FINISHED"}


# ---- live sliders, panel, arrows --------------------------------------------------------------------------------------

def _steps_changed(obj, context):
    if obj.get("restitch_updating") or cached(obj) is None:
        return
    try:
        resize(obj, steps=tuple(obj.restitch_steps), pivot=obj.restitch_pivot)
        warnings = cached(obj)["warnings"]
        context.workspace.status_text_set("restitch: " + "; ".join(warnings) if warnings else None)
    except rs.Error as e:
        context.workspace.status_text_set(f"restitch: {e}")


class VIEW3D_PT_restitch(bpy.types.Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "restitch"
    bl_label = "restitch"

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"

    def draw(self, context):
        obj = context.active_object
        layout = self.layout
        layout.operator("object.restitch_analyze")
        entry = cached(obj)
        if entry is None:
            layout.label(text="Analyse to find the repeats")
            return
        offsets = entry["analysis"].principal_offsets
        if not offsets:
            layout.label(text="No repeat found", icon="ERROR")
        for i, v in enumerate(offsets):
            row = layout.row()
            row.prop(obj, "restitch_steps", index=i, text=f"v{i + 1} ({_pitch(obj, v):.3g})")
        layout.prop(obj, "restitch_pivot")
        box = layout.box()
        box.prop(obj, "restitch_size")
        box.prop(obj, "restitch_exact")
        op = box.operator("object.restitch_resize", text="Resize to size")
        op.size, op.exact, op.pivot = obj.restitch_size, obj.restitch_exact, obj.restitch_pivot
        for i, c in enumerate(entry["analysis"].candidates):
            layout.operator("object.restitch_promote", text=f"Promote candidate {i + 1}").index = i
        row = layout.row()
        row.operator("object.restitch_restore")
        row.operator("object.restitch_apply")
        for w in entry["warnings"]:
            layout.label(text=w, icon="ERROR")


def _draw_arrows():
    import gpu
    from gpu_extras.batch import batch_for_shader
    obj = bpy.context.active_object
    entry = cached(obj) if obj is not None and obj.type == "MESH" else None
    if entry is None or not entry["analysis"].principal_offsets:
        return
    origin = obj.matrix_world.translation
    lines = []
    for v in entry["analysis"].principal_offsets:
        lines += [origin, origin + obj.matrix_world.to_3x3() @ Vector(v)]
    try:
        shader = gpu.shader.from_builtin("3D_UNIFORM_COLOR")
    except ValueError:
        shader = gpu.shader.from_builtin("UNIFORM_COLOR")
    batch = batch_for_shader(shader, "LINES", {"pos": lines})
    shader.bind()
    shader.uniform_float("color", (1.0, 0.6, 0.1, 1.0))
    batch.draw(shader)


classes = (OBJECT_OT_restitch_analyze, OBJECT_OT_restitch_resize, OBJECT_OT_restitch_promote,
           OBJECT_OT_restitch_restore, OBJECT_OT_restitch_apply, VIEW3D_PT_restitch)


def register():
    global _draw_handle
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.Object.restitch_original = PointerProperty(type=bpy.types.Mesh, name="restitch original")
    bpy.types.Object.restitch_steps = IntVectorProperty(name="Steps", size=3, default=(0, 0, 0), min=-64, max=64,
                                                        update=_steps_changed)
    bpy.types.Object.restitch_pivot = EnumProperty(name="Pivot", items=PIVOTS, default="origin")
    bpy.types.Object.restitch_size = FloatVectorProperty(name="Size", size=3, subtype="XYZ_LENGTH", unit="LENGTH")
    bpy.types.Object.restitch_exact = BoolProperty(name="Exact size", default=True)
    if not bpy.app.background:
        _draw_handle = bpy.types.SpaceView3D.draw_handler_add(_draw_arrows, (), "WINDOW", "POST_VIEW")


def unregister():
    global _draw_handle
    if _draw_handle is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_draw_handle, "WINDOW")
        _draw_handle = None
    for name in ("restitch_original", "restitch_steps", "restitch_pivot", "restitch_size", "restitch_exact"):
        delattr(bpy.types.Object, name)
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
    _cache.clear()
