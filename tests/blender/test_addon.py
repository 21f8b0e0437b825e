# The Blender add-on, headless:
#   blender -b --factory-startup --python tests/blender/test_addon.py -- ZIP RESTITCH_CLI WORK_DIR [MODEL.glb...]
# Installs the zip (scripts/pack-blender.sh) as a user would, imports the bookshelf sample (written by the
# tool) and each MODEL with Blender's glTF importer, analyses, resizes by steps and by size, and compares
# with the tool's result for the same input: dimensions, triangle count; material slots, UV maps and the
# object's transform kept. Then undo, the original back, and a .blend saved and opened again. Prints one
# line per check and "blender: N passed, M failed"; exits 1 on any failure.
import json
import os
import subprocess
import sys
import traceback

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
zip_path, cli, work = args[0], args[1], args[2]
models = args[3:]
os.makedirs(work, exist_ok=True)
passed = failed = 0


def check(name, ok, detail=""):
    global passed, failed
    if ok:
        passed += 1
    else:
        failed += 1
    print(f"{'ok' if ok else 'not ok'} - {name}{f' ({detail})' if detail else ''}", flush=True)


def attempt(name, fn):
    try:
        detail = fn()
        check(name, True, detail if isinstance(detail, str) else "")
    except Exception as e:  # the failure is the check's result
        check(name, False, f"{type(e).__name__}: {e} | {traceback.format_exc().splitlines()[-3].strip()}")


def tool(*a):
    return subprocess.run([cli, *a], check=True, capture_output=True, text=True)


def numpy_aliases():
    # Debian's Blender 3.4.1 glTF importer uses numpy.bool, which numpy 1.24 (Debian 12's) removed: without
    # these aliases Blender cannot import any glTF file, whatever the add-ons. Only this test sets them.
    import numpy
    for alias, kind in (("bool", bool), ("int", int), ("float", float), ("object", object)):
        if alias not in numpy.__dict__:
            setattr(numpy, alias, kind)


def import_model(path):
    numpy_aliases()
    """The model as one mesh object (the glTF importer makes one per mesh node; restitch sees the whole)."""
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    bpy.ops.import_scene.gltf(filepath=path)
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    assert meshes, "the importer made no mesh object"
    bpy.ops.object.select_all(action="DESELECT")
    for o in meshes:
        o.select_set(True)
    bpy.context.view_layer.objects.active = meshes[0]
    if len(meshes) > 1:
        bpy.ops.object.join()
    obj = bpy.context.view_layer.objects.active
    # The world transform into the mesh, so the object's local space is the file's (Z up).
    bpy.ops.object.transform_apply(location=True, rotation=True, scale=True)
    return obj


def blender_size(gltf_size):
    # Blender's glTF importer turns +Y up into +Z up: (x, y, z) in the file is (x, -z, y) in Blender.
    return (gltf_size[0], gltf_size[2], gltf_size[1])


def close(a, b, tol):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


attempt("the zip installs and the add-on enables",
        lambda: (bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True),
                 bpy.ops.preferences.addon_enable(module="restitch_blender"),
                 hasattr(bpy.ops.object, "restitch_resize") or (_ for _ in ()).throw(RuntimeError("no operator")))
        and "")

sample = os.path.join(work, "bookshelf.glb")
tool("sample", "bookshelf", "-o", sample)
inputs = [sample] + models
for path in inputs:
    name = os.path.basename(path)
    # The tool's result for +2 along the first principal offset, and by size.
    out_json = os.path.join(work, name + ".json")
    tool("resize", path, "-o", os.path.join(work, name + ".out.glb"), "--steps", "2", "--json", out_json)
    ref = json.load(open(out_json))
    state = {}

    def load():
        obj = import_model(path)
        state["obj"] = obj
        state["slots"] = [s.material.name if s.material else None for s in obj.material_slots]
        state["uv"] = [u.name for u in obj.data.uv_layers]
        state["matrix"] = [list(r) for r in obj.matrix_world]
        state["dims"] = tuple(obj.dimensions)
        state["triangles"] = sum(len(p.vertices) - 2 for p in obj.data.polygons)
        return f"{state['triangles']} triangles, {len(state['slots'])} material slots, UV maps {state['uv']}"

    attempt(f"{name}: imported", load)
    if "obj" not in state:
        continue
    obj = state["obj"]

    def analyse():
        assert bpy.ops.object.restitch_analyze() == {"FINISHED"}
        from restitch_blender import cached
        entry = cached(obj)
        n = len(entry["analysis"].principal_offsets)
        assert n == len(ref["steps_principal"]), f"{n} principal offsets here, {len(ref['steps_principal'])} in the tool"
        return f"{n} principal offset(s)"

    attempt(f"{name}: analysed, as many principal offsets as the tool finds", analyse)

    def by_steps():
        assert bpy.ops.object.restitch_resize(steps=(2, 0, 0)) == {"FINISHED"}
        want = blender_size(ref["size_out"])
        diag = sum(x * x for x in want) ** 0.5
        assert close(tuple(obj.dimensions), want, 1e-4 * diag), f"dimensions {tuple(obj.dimensions)}, the tool {want}"
        tris = sum(len(p.vertices) - 2 for p in obj.data.polygons)
        assert tris == ref["output"]["triangles"], f"{tris} triangles, the tool {ref['output']['triangles']}"
        assert [s.material.name if s.material else None for s in obj.material_slots] == state["slots"], "material slots"
        assert [u.name for u in obj.data.uv_layers] == state["uv"], f"UV maps {[u.name for u in obj.data.uv_layers]}"
        assert [list(r) for r in obj.matrix_world] == state["matrix"], "the object's transform changed"
        assert obj.restitch_original is not None and obj.data is not obj.restitch_original
        assert tuple(obj.restitch_steps)[0] == 2
        return f"{tris} triangles, {tuple(round(x, 4) for x in obj.dimensions)}"

    attempt(f"{name}: resized by steps (2, 0, 0) as the tool does", by_steps)

    def by_size():
        # 1.37 times as long along the axis the first principal offset runs along (the object's local axes).
        from restitch_blender import cached
        v = cached(obj)["analysis"].principal_offsets[0]
        axis = max(range(3), key=lambda k: abs(v[k]))
        size = [0.0, 0.0, 0.0]
        size[axis] = state["dims"][axis] * 1.37
        assert bpy.ops.object.restitch_resize(size=size, exact=True) == {"FINISHED"}
        assert abs(obj.dimensions[axis] - size[axis]) <= 1e-5 * size[axis], f"{obj.dimensions[axis]} for {size[axis]}"
        for k in range(3):
            if k != axis:
                assert abs(obj.dimensions[k] - state["dims"][k]) <= 1e-5 * max(state["dims"]), "another axis changed"
        return f"{'xyz'[axis]} {obj.dimensions[axis]:.5g}"

    attempt(f"{name}: resized to a size, exactly", by_size)

    def cursor_pivot():
        # The 3D cursor at the high end along the first principal offset: that end stays put, the low end moves.
        from restitch_blender import cached
        bpy.ops.object.restitch_restore()
        v = cached(obj)["analysis"].principal_offsets[0]
        axis = max(range(3), key=lambda k: abs(v[k]))
        lo = min(c[axis] for c in obj.bound_box)
        hi = max(c[axis] for c in obj.bound_box)
        cursor = [0.0, 0.0, 0.0]
        cursor[axis] = hi
        bpy.context.scene.cursor.location = obj.matrix_world @ __import__("mathutils").Vector(cursor)
        assert bpy.ops.object.restitch_resize(steps=(1, 0, 0), pivot="cursor") == {"FINISHED"}
        lo2 = min(c[axis] for c in obj.bound_box)
        hi2 = max(c[axis] for c in obj.bound_box)
        tol = 1e-5 * (hi - lo)
        assert abs(hi2 - hi) <= tol, f"the end at the cursor moved: {hi} -> {hi2}"
        assert abs((lo - lo2) - abs(v[axis])) <= 1e-4 * (hi - lo), f"the other end moved by {lo - lo2}, a period is {abs(v[axis])}"
        bpy.context.scene.cursor.location = (0, 0, 0)
        return f"{'xyz'[axis]} from [{lo:.4g}, {hi:.4g}] to [{lo2:.4g}, {hi2:.4g}]"

    attempt(f"{name}: the 3D cursor pivot keeps what lies at the cursor", cursor_pivot)

    def slider():
        obj.restitch_steps = (1, 0, 0)  # the panel's slider: a live resize
        tris = sum(len(p.vertices) - 2 for p in obj.data.polygons)
        assert tris != state["triangles"], "the slider did not resize"
        return f"{tris} triangles"

    attempt(f"{name}: the slider resizes live", slider)

    def undo_and_restore():
        bpy.ops.ed.undo_push(message="before restitch")
        bpy.ops.object.restitch_resize(steps=(-1, 0, 0))
        after = sum(len(p.vertices) - 2 for p in obj.data.polygons)
        bpy.ops.object.restitch_restore()
        tris = sum(len(p.vertices) - 2 for p in obj.data.polygons)
        assert tris == state["triangles"], f"restored {tris}, the input had {state['triangles']}"
        assert obj.restitch_original is None
        assert close(tuple(obj.dimensions), state["dims"], 1e-6 * max(state["dims"])), "dimensions after restore"
        return f"-1 gave {after} triangles; the original back"

    attempt(f"{name}: the original comes back", undo_and_restore)

blend = os.path.join(work, "restitch.blend")


def save_and_open():
    obj = bpy.context.view_layer.objects.active
    bpy.ops.object.restitch_resize(steps=(1, 0, 0))
    tris = sum(len(p.vertices) - 2 for p in obj.data.polygons)
    name = obj.name
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    bpy.ops.wm.open_mainfile(filepath=blend)
    again = bpy.data.objects[name]
    assert sum(len(p.vertices) - 2 for p in again.data.polygons) == tris
    assert again.restitch_original is not None, "the original mesh was not saved with the result"
    return f"{os.path.getsize(blend)} bytes"


attempt("a .blend with a resized object saves and opens with its original kept", save_and_open)


def undo():
    # A resize, then undo: the mesh shown before it is back (objects are looked up again: undo reloads data).
    obj = bpy.context.view_layer.objects.active
    name = obj.name
    before = sum(len(p.vertices) - 2 for p in obj.data.polygons)
    bpy.ops.ed.undo_push(message="before the resize")
    assert bpy.ops.object.restitch_resize(steps=(3, 0, 0)) == {"FINISHED"}
    bpy.ops.ed.undo_push(message="the resize")
    grown = sum(len(p.vertices) - 2 for p in bpy.data.objects[name].data.polygons)
    assert grown != before, "the resize changed nothing"
    bpy.ops.ed.undo()
    back = sum(len(p.vertices) - 2 for p in bpy.data.objects[name].data.polygons)
    assert back == before, f"after undo {back} triangles, before the resize {before}"
    return f"{before} -> {grown} -> {back} triangles"


attempt("a resize is undone by one undo", undo)
print(f"blender: {passed} passed, {failed} failed", flush=True)
sys.exit(1 if failed else 0)
