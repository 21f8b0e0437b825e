// layers.js - the worker's arrays made into three.js objects; no DOM, no state of its own.
//
//   modelObjects({mesh, view, materials, result}) -> {model, seams}   the model in one of the views:
//       'shaded' (its own materials), 'labels' (output cells coloured by label, paper Fig. 4c) or
//       'seams' (grey, plus the faces between differently labelled cells; seams is null otherwise).
//       In 'labels' and 'seams' a seam whose mismatch passes the tolerance (docs/method.md 2.8) is red:
//       its cell face, and the model's faces near it (result.seam_faces). In every view the result's
//       open edges that the input does not have (result.open_edges, the result check's "open seam",
//       docs/method.md 2.11) are drawn as red lines on top.
//   offsetArrows(principalOffsets, box) -> [ArrowHelper]   principal offsets from the box's centre (paper Fig. 2)
//   histogramObjects(analysis, extras) -> [Object3D]           offsets of all matches and the dominant
//                                                              (candidates in cyan) and principal offsets,
//                                                              in normalized units
//   materialsFromGlb(glb) -> promise of [Material]             the materials (and textures) of a .glb
//   boxOf(info) -> Box3                                        a loaded model's bounding box (model units)
//   disposeGroup(group)                                        empties a group, freeing what it owned
// `mesh` is the worker's {positions, normals?, uvs?, colors?, indices, groups}, `result` a retarget answer
// (face_labels, cell_labels, grid, report); materials built here are marked userData.owned, so disposeGroup
// frees them and leaves the model's shared materials alone.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

export const AXIS_COLORS = [0xe0483e, 0x3ec94a, 0x3e7de0];

const defaultMaterial = new THREE.MeshStandardMaterial({ color: 0xb0b0b0, roughness: 0.8 });
const neutralMaterial = new THREE.MeshStandardMaterial({ color: 0x9a9a9a, roughness: 0.85, side: THREE.DoubleSide });

function owned(material) {
  material.userData.owned = true;
  return material;
}

export function disposeGroup(group) {
  for (const child of [...group.children]) {
    group.remove(child);
    child.traverse((o) => {
      if (o.geometry) o.geometry.dispose();
      for (const m of [o.material || []].flat()) if (m.userData.owned) m.dispose();
    });
  }
}

export function boxOf(info) {
  return new THREE.Box3(new THREE.Vector3(...info.bbox_min), new THREE.Vector3(...info.bbox_max));
}

export async function materialsFromGlb(glb) {
  if (!glb) return [];
  try {
    const gltf = await new GLTFLoader().parseAsync(glb.buffer, '');
    return await gltf.parser.getDependencies('material');
  } catch (e) {
    console.warn('restitch demo: materials could not be read, showing grey:', e);
    return [];
  }
}

function geometryOf(mesh) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(mesh.positions, 3));
  if (mesh.normals) g.setAttribute('normal', new THREE.BufferAttribute(mesh.normals, 3));
  if (mesh.uvs) g.setAttribute('uv', new THREE.BufferAttribute(mesh.uvs, 2));
  if (mesh.colors) g.setAttribute('color', new THREE.BufferAttribute(mesh.colors, 4));
  g.setIndex(new THREE.BufferAttribute(mesh.indices, 1));
  mesh.groups.forEach((grp, i) => g.addGroup(grp.start, grp.count, i));
  if (!mesh.normals) g.computeVertexNormals();
  g.computeBoundingBox();
  g.computeBoundingSphere();
  return g;
}

// The material of a draw group: the model's own, or grey; a copy with vertex colours when the group has them.
function materialFor(group, materials) {
  let m = materials[group.material] || defaultMaterial;
  if (group.colors) {
    m = owned(m.clone());
    m.vertexColors = true;
  }
  return m;
}

// Distinct colours for label indices (golden-ratio hues).
function labelColor(label, out) {
  return out.setHSL((label * 0.618033988749895 + 0.1) % 1, 0.7, 0.45);
}

export const SEAM_OVER_COLOR = 0xe01010;
const seamOver = new THREE.Color(SEAM_OVER_COLOR), grey = new THREE.Color(0x9a9a9a);

// Non-indexed copy with one colour per face: the output cells coloured by their label (paper Fig. 4c), or
// grey without labels; faces flagged in `seamFaces` (near a seam over the tolerance) red.
function labelGeometry(mesh, faceLabels, seamFaces = null, plain = false) {
  const idx = mesh.indices, pos = mesh.positions, nor = mesh.normals;
  const n = idx.length;
  const p = new Float32Array(n * 3), c = new Float32Array(n * 3), nn = nor ? new Float32Array(n * 3) : null;
  const col = new THREE.Color();
  for (let i = 0; i < n; ++i) {
    const v = idx[i];
    p[3 * i] = pos[3 * v]; p[3 * i + 1] = pos[3 * v + 1]; p[3 * i + 2] = pos[3 * v + 2];
    if (nn) { nn[3 * i] = nor[3 * v]; nn[3 * i + 1] = nor[3 * v + 1]; nn[3 * i + 2] = nor[3 * v + 2]; }
    if (i % 3 === 0) {
      if (seamFaces && seamFaces[i / 3]) col.copy(seamOver);
      else if (plain) col.copy(grey);
      else labelColor(faceLabels ? faceLabels[i / 3] : 0, col);
    }
    c[3 * i] = col.r; c[3 * i + 1] = col.g; c[3 * i + 2] = col.b;
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(p, 3));
  g.setAttribute('color', new THREE.BufferAttribute(c, 3));
  if (nn) g.setAttribute('normal', new THREE.BufferAttribute(nn, 3));
  else g.computeVertexNormals();
  return g;
}

// The seams over the tolerance, as keys "i,j,k|i,j,k" (both orders) of their two output cells.
function seamsOver(result) {
  const over = new Set();
  const r = result.report;
  for (const s of r.seams || []) {
    if (!(s.mismatch > r.seam_tolerance)) continue;
    over.add(`${s.cells[0]}|${s.cells[1]}`);
    over.add(`${s.cells[1]}|${s.cells[0]}`);
  }
  return over;
}

// The seam faces as flat arrays: every face shared by two 6-neighbour output cells with different labels
// (where the seam's plane lies),
// as triangles (quads) and as outlines (lines), in model units; those of seams over the tolerance (and the
// ends copied from elsewhere that are) in `badQuads` instead.
export function seamFaces(result) {
  const [U, V, W] = result.report.cells_out;
  const labels = result.cell_labels;
  const A = result.grid.axes.map((a) => new THREE.Vector3(...a));
  const o = new THREE.Vector3(...result.grid.origin);
  const toModel = (c) => o.clone().addScaledVector(A[0], c[0]).addScaledVector(A[1], c[1]).addScaledVector(A[2], c[2]);
  const quads = [], lines = [], badQuads = [];
  const over = seamsOver(result);
  const at = (i, j, k) => labels[i + U * (j + V * k)];
  // A seam's plane may lie off its cell plane (report.plane_offsets, docs/method.md 2.9).
  const offsets = result.report.plane_offsets || [[], [], []];
  const offset = (a, i) => (offsets[a] && offsets[a].length ? offsets[a][i] : 0);
  const dims = [U, V, W];
  for (let k = 0; k < W; ++k) for (let j = 0; j < V; ++j) for (let i = 0; i < U; ++i) {
    const x = [i, j, k];
    for (let a = 0; a < 3; ++a) {
      const y = x.slice(); y[a] += 1;
      const lowEnd = x.slice(); lowEnd[a] -= 1;
      if (x[a] === 0 && over.has(`${x}|${lowEnd}`)) {  // an end over the tolerance: its outer face
        const b = (a + 1) % 3, c = (a + 2) % 3;
        for (const [s, t] of [[0, 0], [1, 0], [1, 1], [0, 0], [1, 1], [0, 1]]) {
          const q = x.slice(); q[b] += s; q[c] += t;
          const p = toModel(q);
          badQuads.push(p.x, p.y, p.z);
        }
      }
      if (y[a] >= dims[a] && over.has(`${x}|${y}`)) {
        const b = (a + 1) % 3, c = (a + 2) % 3;
        for (const [s, t] of [[0, 0], [1, 0], [1, 1], [0, 0], [1, 1], [0, 1]]) {
          const q = x.slice(); q[a] += 1; q[b] += s; q[c] += t;
          const p = toModel(q);
          badQuads.push(p.x, p.y, p.z);
        }
      }
      if (y[a] >= dims[a] || at(...x) === at(...y)) continue;
      const b = (a + 1) % 3, c = (a + 2) % 3;
      const corners = [[0, 0], [1, 0], [1, 1], [0, 1]].map(([s, t]) => {
        const q = x.slice(); q[a] += 1 + offset(a, y[a]); q[b] += s; q[c] += t;
        return toModel(q);
      });
      const target = over.has(`${x}|${y}`) ? badQuads : quads;
      for (const idx of [0, 1, 2, 0, 2, 3]) target.push(corners[idx].x, corners[idx].y, corners[idx].z);
      for (let e = 0; e < 4; ++e) {
        const p = corners[e], q = corners[(e + 1) % 4];
        lines.push(p.x, p.y, p.z, q.x, q.y, q.z);
      }
    }
  }
  return { quads, lines, badQuads };
}

function seamObject(result) {
  const { quads, lines, badQuads } = seamFaces(result);
  const group = new THREE.Group();
  if (badQuads.length) {
    const bg = new THREE.BufferGeometry();
    bg.setAttribute('position', new THREE.Float32BufferAttribute(badQuads, 3));
    const bm = owned(new THREE.MeshBasicMaterial({ color: SEAM_OVER_COLOR, transparent: true, opacity: 0.55,
                                                   side: THREE.DoubleSide, depthWrite: false }));
    const bad = new THREE.Mesh(bg, bm);
    bad.name = 'seams-over-tolerance';
    group.add(bad);
  }
  if (!quads.length) return group;
  const qg = new THREE.BufferGeometry();
  qg.setAttribute('position', new THREE.Float32BufferAttribute(quads, 3));
  const qm = owned(new THREE.MeshBasicMaterial({ color: 0xff8a1c, transparent: true, opacity: 0.35,
                                                 side: THREE.DoubleSide, depthWrite: false }));
  const lg = new THREE.BufferGeometry();
  lg.setAttribute('position', new THREE.Float32BufferAttribute(lines, 3));
  const lm = owned(new THREE.LineBasicMaterial({ color: 0xffb060 }));
  group.add(new THREE.Mesh(qg, qm), new THREE.LineSegments(lg, lm));
  return group;
}

// The result's new open edges (6 floats per edge) as red lines drawn over the model, or null.
function openEdgeLines(result) {
  const e = result && result.open_edges;
  if (!e || e.length === 0) return null;
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(e, 3));
  const lines = new THREE.LineSegments(g, owned(new THREE.LineBasicMaterial({ color: SEAM_OVER_COLOR, depthTest: false })));
  lines.renderOrder = 5;
  lines.name = 'open-edges';
  return lines;
}

export function modelObjects(args) {
  const objects = modelObjectsOf(args);
  const lines = openEdgeLines(args.result);
  if (lines) objects.model.add(lines);
  return objects;
}

function modelObjectsOf({ mesh, view, materials = [], result = null }) {
  if (view === 'labels') {
    const m = owned(new THREE.MeshStandardMaterial({ vertexColors: true, roughness: 0.75, side: THREE.DoubleSide }));
    return { model: new THREE.Mesh(labelGeometry(mesh, result ? result.face_labels : null,
                                                 result ? result.seam_faces : null), m), seams: null };
  }
  if (view === 'seams') {
    const flagged = result && result.seam_faces && result.seam_faces.some((f) => f);
    const model = flagged
      ? new THREE.Mesh(labelGeometry(mesh, null, result.seam_faces, true),
                       owned(new THREE.MeshStandardMaterial({ vertexColors: true, roughness: 0.85, side: THREE.DoubleSide })))
      : new THREE.Mesh(geometryOf(mesh), neutralMaterial);
    return { model, seams: result ? seamObject(result) : null };
  }
  return { model: new THREE.Mesh(geometryOf(mesh), mesh.groups.map((g) => materialFor(g, materials))), seams: null };
}

export function offsetArrows(principalOffsets, box) {
  const center = box.getCenter(new THREE.Vector3());
  return principalOffsets.map((v, i) => {
    const dir = new THREE.Vector3(...v);
    const len = dir.length();
    const arrow = new THREE.ArrowHelper(dir.clone().normalize(), center, len, AXIS_COLORS[i], len * 0.25, len * 0.12);
    arrow.line.material.depthTest = false;
    arrow.cone.material.depthTest = false;
    arrow.renderOrder = 10;
    return arrow;
  });
}

export function histogramObjects(analysis, extras) {
  const out = [];
  const pg = new THREE.BufferGeometry();
  pg.setAttribute('position', new THREE.BufferAttribute(extras.match_offsets, 3));
  out.push(new THREE.Points(pg, owned(new THREE.PointsMaterial({ color: 0x8a8f98, size: 1.5, sizeAttenuation: false }))));
  const candidate = new Set((analysis.candidates || []).map((c) => c.dominant));
  for (const [wanted, color, size] of [[false, 0xffa030, 7], [true, 0x40d8f0, 9]]) {
    const dom = extras.dominant_normalized.filter((_, i) => candidate.has(i) === wanted).flat();
    if (!dom.length) continue;
    const dg = new THREE.BufferGeometry();
    dg.setAttribute('position', new THREE.Float32BufferAttribute(dom, 3));
    out.push(new THREE.Points(dg, owned(new THREE.PointsMaterial({ color, size, sizeAttenuation: false }))));
  }
  analysis.principal_offsets.forEach((v, i) => {
    const dir = new THREE.Vector3(...v).multiplyScalar(analysis.scale);
    const len = dir.length();
    out.push(new THREE.ArrowHelper(dir.clone().normalize(), new THREE.Vector3(), len, AXIS_COLORS[i],
                                   Math.min(0.15, len * 0.3), Math.min(0.08, len * 0.15)));
  });
  return out;
}
