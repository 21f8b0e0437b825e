#!/usr/bin/env python3
"""Writes the hand-made seeds of tests/fuzz/corpus (run from anywhere; deterministic):
small glTF models (a row of boxes as .glb and as .gltf with an embedded buffer, a single
triangle, a model with two primitives and a node matrix), MRF problems and xyzn point sets.
The bundled samples are added by scripts/fuzz.sh at run time (they are generated, not stored)."""
import base64, json, os, struct

here = os.path.dirname(os.path.abspath(__file__))
corpus = os.path.join(here, "corpus")

def boxes(n, pitch=1.0):
    pos, idx = [], []
    quads = [(0, 2, 6, 4), (1, 5, 7, 3), (0, 4, 5, 1), (2, 3, 7, 6), (0, 1, 3, 2), (4, 6, 7, 5)]
    for k in range(n):
        lo, hi = (k * pitch, 0.0, 0.0), (k * pitch + 0.4, 1.0, 0.2)
        base = len(pos)
        for c in range(8):
            pos.append((hi[0] if c & 1 else lo[0], hi[1] if c & 2 else lo[1], hi[2] if c & 4 else lo[2]))
        for q in quads:
            idx += [base + q[0], base + q[1], base + q[2], base + q[0], base + q[2], base + q[3]]
    return pos, idx

def gltf(pos, idx, matrix=None, two_primitives=False):
    pbytes = b"".join(struct.pack("<3f", *p) for p in pos)
    ibytes = b"".join(struct.pack("<I", i) for i in idx)
    buf = pbytes + ibytes
    lo = [min(p[a] for p in pos) for a in range(3)]
    hi = [max(p[a] for p in pos) for a in range(3)]
    prims = [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]
    if two_primitives:
        prims.append({"attributes": {"POSITION": 0}, "indices": 1})
    node = {"mesh": 0}
    if matrix:
        node["matrix"] = matrix
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [node],
           "meshes": [{"primitives": prims}],
           "buffers": [{"byteLength": len(buf)}],
           "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pbytes), "target": 34962},
                           {"buffer": 0, "byteOffset": len(pbytes), "byteLength": len(ibytes), "target": 34963}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": lo, "max": hi},
                         {"bufferView": 1, "componentType": 5125, "count": len(idx), "type": "SCALAR"}]}
    return doc, buf

def glb(doc, buf):
    js = json.dumps(doc, separators=(",", ":"), sort_keys=True).encode()
    js += b" " * (-len(js) % 4)
    buf += b"\0" * (-len(buf) % 4)
    body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(buf), 0x004E4942) + buf
    return struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body

def embedded(doc, buf):
    doc = json.loads(json.dumps(doc))
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(buf).decode()
    return json.dumps(doc, indent=1, sort_keys=True).encode()

def write(sub, name, data):
    with open(os.path.join(corpus, sub, name), "wb") as f:
        f.write(data)

row = gltf(*boxes(6))
for sub in ("gltf", "pipeline"):
    write(sub, "row6.glb", glb(*row))
    write(sub, "row3.gltf", embedded(*gltf(*boxes(3))))
write("gltf", "triangle.glb", glb(*gltf([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [0, 1, 2])))
write("gltf", "matrix_two_primitives.glb",
      glb(*gltf(*boxes(2), matrix=[2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1], two_primitives=True)))
write("pipeline", "row2.glb", glb(*gltf(*boxes(2))))

write("mrf", "chain.mrf", b"restitch-mrf 1\n# a chain of 3 nodes, 2 labels\nnodes 3 labels 2 edges 2\n0 1\n1 0\n0.5 0.5\n"
      b"0 1\n0 1\n1 0\n1 2\n0 2\n2 0\n")
write("mrf", "empty.mrf", b"restitch-mrf 1\nnodes 0 labels 0 edges 0\n")
write("mrf", "crlf.mrf", b"restitch-mrf 1\r\nnodes 2 labels 3 edges 1\r\n1 2 3\r\n3 2 1\r\n0 1\r\n0 1 2\r\n1 0 1\r\n2 1 0\r\n")
write("xyzn", "grid.xyzn", b"".join(b"%g %g 0 0 0 1\n" % (x * 0.1, y * 0.1) for x in range(6) for y in range(6)))
write("xyzn", "comments_nan.xyzn", b"# points\n0 0 0 0 0 1\r\n\n1 0 0 nan 0 1\n0 1 0 0 0 1\n  0 0 1\t0 1 0\n")
