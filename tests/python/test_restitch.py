"""Tests of the Python module restitch (examples/python), run by ctest (test `python`) with pytest.

PYTHONPATH points at the built module; RESTITCH_CLI at the command-line tool, whose outputs the module's
must equal byte for byte; RESTITCH_MODELS at ../shared/models (tests that need it skip when it is absent).
"""
import json
import os
import subprocess
import threading
import time

import numpy as np
import pytest

import restitch

CLI = os.environ.get("RESTITCH_CLI", "")
MODELS = os.environ.get("RESTITCH_MODELS", "")


def cli(*args):
    if not CLI or not os.path.exists(CLI):
        pytest.fail("RESTITCH_CLI does not name the restitch tool")
    return subprocess.run([CLI, *args], check=True, capture_output=True, text=True)


@pytest.fixture(scope="module")
def bookshelf(tmp_path_factory):
    path = tmp_path_factory.mktemp("in") / "bookshelf.glb"
    cli("sample", "bookshelf", "-o", str(path))
    return path


def area(mesh, material):
    p = mesh.positions.astype(np.float64)[mesh.triangles[mesh.material_ids == material]]
    return 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum()


def test_version_and_policies():
    assert restitch.__version__.count(".") == 2
    p = restitch.policies()
    assert p["descriptors"][0] == "shot" and "fpfh" in p["descriptors"]
    assert p["label_spaces"][0] == "lattice"
    assert "bookshelf" in restitch.samples()


def test_the_samples_exact_results(tmp_path):
    # Each sample grown by two repeats along its count's principal offset equals the sample generated with two
    # more: the same box in place, the same area per material.
    for name, parameter, start in [("bookshelf", "columns", 4), ("fence", "pickets", 8), ("pin_header", "pins", 4)]:
        mesh = restitch.sample(name, **{parameter: start})
        analysis = restitch.analyze(mesh, threads=1)
        truth = restitch.sample(name, **{parameter: start + 2})
        r = restitch.Retargeter(mesh, analysis)
        # The principal offset along the count parameter's axis.
        (lo, hi), (tlo, thi) = mesh.bounds, truth.bounds
        grow = np.subtract(thi, tlo) - np.subtract(hi, lo)
        axis = int(np.argmax(np.abs(grow)))
        index = max(range(len(analysis.principal_offsets)), key=lambda i: abs(analysis.principal_offsets[i][axis]))
        steps = [0] * len(analysis.principal_offsets)
        steps[index] = 2
        out = r.resize(steps=steps)
        assert out.steps == steps
        assert out.warnings == [], out.warnings
        size = np.subtract(out.mesh.bounds[1], out.mesh.bounds[0])
        np.testing.assert_allclose(size, np.subtract(thi, tlo), atol=1e-4 * np.linalg.norm(size))
        np.testing.assert_allclose(out.mesh.bounds[0], tlo, atol=1e-4 * np.linalg.norm(size))  # in place
        # The same surface per material (seams cut triangles, so counts differ; areas do not).
        for material in sorted(set(truth.material_ids.tolist())):
            a, b = area(out.mesh, material), area(truth, material)
            assert abs(a - b) <= 1e-4 * b, (name, material, a, b)


def test_the_same_bytes_as_the_tool(bookshelf, tmp_path):
    mesh = restitch.load(str(bookshelf))
    analysis = restitch.analyze(mesh, threads=1)
    r = restitch.Retargeter(mesh, analysis, pivot="center")
    out = r.resize(steps=[2, 1])
    cli("resize", str(bookshelf), "-o", str(tmp_path / "cli.glb"), "--steps", "2,1", "--pivot", "center",
        "--threads", "1", "--json", str(tmp_path / "cli.json"))
    assert out.mesh.to_glb() == (tmp_path / "cli.glb").read_bytes()
    report = json.loads((tmp_path / "cli.json").read_text())
    for key in ("steps", "size_out", "cells_out", "output", "seams", "warnings", "pivot"):
        assert out.report[key] == report[key], key
    # By size, exact: the size asked, to float precision.
    want = (2.3, 0.0, 0.0)
    exact = r.resize(size=want, exact=True)
    cli("resize", str(bookshelf), "-o", str(tmp_path / "size.glb"), "--size", "2.3,0,0", "--exact", "--pivot",
        "center", "--threads", "1")
    assert exact.mesh.to_glb() == (tmp_path / "size.glb").read_bytes()
    got = exact.mesh.bounds
    assert abs((got[1][0] - got[0][0]) - 2.3) < 1e-5
    assert r.steps_for_size(want) == exact.steps


def test_round_trips(bookshelf, tmp_path):
    mesh = restitch.load(str(bookshelf))
    # glb bytes -> mesh -> glb bytes
    again = restitch.loads(mesh.to_glb())
    assert again.to_glb() == mesh.to_glb()
    # arrays -> mesh: the same geometry, attributes and materials; the same analysis
    copy = restitch.Mesh(mesh.positions, mesh.triangles, normals=mesh.normals, uvs=mesh.uvs,
                         material_ids=mesh.material_ids)
    assert copy.triangle_count == mesh.triangle_count
    assert copy.vertex_count == mesh.vertex_count
    np.testing.assert_array_equal(copy.positions[copy.triangles], mesh.positions[mesh.triangles])
    np.testing.assert_array_equal(copy.uvs[0][copy.triangles], mesh.uvs[0][mesh.triangles])
    np.testing.assert_array_equal(copy.material_ids, mesh.material_ids)
    a, b = restitch.analyze(mesh, threads=1), restitch.analyze(copy, threads=1)
    assert a.principal_offsets == b.principal_offsets
    assert a.lattice["cells"] == [4, 4, a.lattice["cells"][2]]  # 4 columns, 4 shelves
    assert a.lattice["resizable"][:2] == [True, True] and a.report["lattice_axes"] == a.lattice["axes"]
    # save -> load
    path = tmp_path / "saved.glb"
    mesh.save(str(path))
    assert path.read_bytes() == mesh.to_glb()
    assert restitch.load(str(path)).triangle_count == mesh.triangle_count


def test_arrays_of_a_plain_mesh():
    # Two quads side by side of one material each; a vertex shared by both materials is split.
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0]], dtype=np.float64)
    triangles = np.array([[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]])
    mesh = restitch.Mesh(positions, triangles, material_ids=[1, 1, 0, 0])
    assert mesh.triangle_count == 4
    assert mesh.vertex_count == 8  # vertices 1 and 2 are in both groups
    assert sorted(set(mesh.material_ids.tolist())) == [0, 1]
    assert mesh.positions.dtype == np.float32 and mesh.triangles.shape == (4, 3)
    assert mesh.normals is None and mesh.uvs == [] and mesh.colors is None
    assert mesh.bounds == ((0.0, 0.0, 0.0), (2.0, 1.0, 0.0))


def test_errors_carry_the_library_code(tmp_path):
    def code(call):
        with pytest.raises(restitch.Error) as e:
            call()
        assert str(e.value)  # a message in words
        return e.value.code

    assert code(lambda: restitch.load(str(tmp_path / "missing.glb"))) == "io_error"
    assert code(lambda: restitch.loads(b"not a gltf")) == "parse_error"
    assert code(lambda: restitch.sample("no such sample")) == "invalid_argument"
    assert code(lambda: restitch.Mesh(np.zeros((3, 3)), [[0, 1, 5]])) == "invalid_argument"
    assert code(lambda: restitch.Mesh(np.zeros((3, 2)), [[0, 1, 2]])) == "invalid_argument"
    assert code(lambda: restitch.Mesh(np.zeros((3, 3)), [[0, 1, 2]])) == "invalid_mesh"  # no area
    mesh = restitch.sample("fence")
    assert code(lambda: restitch.analyze(mesh, descriptor="nope")) == "invalid_argument"
    analysis = restitch.analyze(mesh, threads=1)
    r = restitch.Retargeter(mesh, analysis)
    assert code(lambda: r.resize()) == "invalid_argument"
    assert code(lambda: r.resize(steps=[1], size=[1, 0, 0])) == "invalid_argument"
    assert code(lambda: r.resize(steps=[0, 1])) == "invalid_argument"  # the fence has one principal offset
    assert code(lambda: r.resize(size=[-1, 0, 0])) == "invalid_argument"
    assert code(lambda: restitch.Retargeter(restitch.sample("fence"), analysis)) == "invalid_argument"
    assert code(lambda: restitch.Retargeter(mesh, analysis, label_space="nope")) == "invalid_argument"
    flat = restitch.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), [[0, 1, 2]])
    none = restitch.analyze(flat, threads=1)
    assert none.principal_offsets == []
    assert code(lambda: restitch.Retargeter(flat, none).resize(steps=[1])) in ("no_repetition", "invalid_argument")


def test_promote_returns_a_new_analysis():
    mesh = restitch.sample("fence")
    analysis = restitch.analyze(mesh, threads=1)
    assert len(analysis.principal_offsets) == 1
    rails = [c["offset"] for c in analysis.candidates]
    assert rails, "the fence's rails are a candidate"
    promoted = analysis.promote([rails[0]])
    assert len(analysis.principal_offsets) == 1  # unchanged
    assert np.allclose(promoted.principal_offsets[0], rails[0], atol=1e-3)
    out = restitch.Retargeter(mesh, promoted).resize(steps=[1])
    grow = np.subtract(out.mesh.bounds[1], out.mesh.bounds[0]) - np.subtract(mesh.bounds[1], mesh.bounds[0])
    assert np.allclose(grow, np.abs(promoted.principal_offsets[0]), atol=1e-3)


def test_the_gil_is_released_during_analysis():
    # A thread that counts while the analysis runs counts on: the analysis does not hold the GIL.
    mesh = restitch.sample("bookshelf")
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    start = time.perf_counter()
    restitch.analyze(mesh, threads=1)
    end = time.perf_counter()
    done.set()
    t.join()
    during = [x for x in ticks if start < x < end]
    assert end - start > 0.05
    assert len(during) > 10, f"{len(during)} ticks during a {end - start:.2f} s analysis"


def test_a_shared_model_as_the_tool_does(tmp_path):
    path = os.path.join(MODELS, "sh3d-default_railing.glb")
    if not os.path.exists(path):
        pytest.skip("../shared/models is absent")
    mesh = restitch.load(path)
    out = restitch.Retargeter(mesh, restitch.analyze(mesh, threads=1)).resize(steps=[-1])
    cli("resize", path, "-o", str(tmp_path / "cli.glb"), "--steps", "-1", "--threads", "1")
    assert out.mesh.to_glb() == (tmp_path / "cli.glb").read_bytes()
