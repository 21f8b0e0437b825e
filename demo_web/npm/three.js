// restitch/three - resize three.js objects along their repeats.
//
//   import { analyze } from 'restitch/three';
//   const resizable = await analyze(gltf.scene);        // finds the repeats once (the analysis is cached)
//   resizable.resize({ steps: [2, 0, 0] });              // in place: each mesh gets its share of the result
//   slider.oninput = () => resizable.resize({ size: [slider.value, 0, 0], exact: true });
//   resizable.restore();                                 // the original geometries back
//   resizable.dispose();                                 // frees the WebAssembly memory
//
// What is resized: a BufferGeometry, a Mesh, or any Object3D (a loaded glTF scene) with every Mesh under
// it taken together as one model, in the frame of the object given (its own transform is not applied, so
// sizes and steps are in its local units). Each mesh keeps its material (or its material array and group
// slots), its transform and which attributes it had: position, normal, uv .. uv3, color. The result of a
// mesh is built in its own frame again (inverse of its transform relative to the root), so a glTF scene
// keeps its node hierarchy. Meshes with morph targets or skinning are resized as their bind-pose geometry;
// instanced meshes and points/lines are left out.
//
// Caching: `analyze(target)` remembers its Resizable for `target` (WeakMap), so `resize(target, ...)`
// called on every slider move pays for the resize only. Each resize starts from the original geometry, not
// from the last result. `into: 'new'` leaves `target` as it was and returns a resized copy (a clone sharing
// materials). Three is a peer dependency: this file imports 'three' and nothing else from it.
import { BufferAttribute, BufferGeometry, Matrix3, Matrix4, Vector3 } from 'three';
import { init, RestitchError } from './index.js';

const uvNames = ['uv', 'uv1', 'uv2', 'uv3'];
let shared = null;  // one module instance for every object (init() once)
const cache = new WeakMap();

function restitchModule(options) {
  if (options && options.restitch) return Promise.resolve(options.restitch);
  if (!shared) shared = init();
  return shared;
}

// The meshes to resize under `target`, in traversal order (clones traverse in the same order).
function meshesOf(target) {
  const out = [];
  target.traverse((o) => {
    if (o.isMesh && !o.isInstancedMesh && o.geometry && o.geometry.isBufferGeometry && o.geometry.attributes.position) out.push(o);
  });
  return out;
}

// One part per (mesh, material slot): its index range of the mesh's geometry.
function partsOf(geometry, multiMaterial) {
  const count = geometry.index ? geometry.index.count : geometry.attributes.position.count;
  const start = Math.max(0, geometry.drawRange.start);
  const end = Math.min(count, geometry.drawRange.start + geometry.drawRange.count);
  if (!multiMaterial || geometry.groups.length === 0) return [{ start, end, materialIndex: 0 }];
  return geometry.groups
    .map((g) => ({ start: Math.max(start, g.start), end: Math.min(end, g.start + g.count), materialIndex: g.materialIndex ?? 0 }))
    .filter((g) => g.end > g.start);
}

// The model as restitch arrays, in the root's frame, and the map back from restitch's groups.
function gather(sources) {
  const uvSets = Math.max(0, ...sources.map((s) => 1 + Math.max(-1, ...s.had.uvs)));
  const anyColor = sources.some((s) => s.geometry.attributes.color);
  const positions = [], normals = [], colors = [], indices = [], groups = [], parts = [];
  const uvs = Array.from({ length: uvSets }, () => []);
  const p = new Vector3();
  sources.forEach((src, s) => {
    let g = src.geometry;
    if (!g.attributes.normal) {  // restitch reads shape from normals too: computed here, not given back
      g = g.clone();
      g.computeVertexNormals();
    }
    const a = g.attributes;
    const normalMatrix = new Matrix3().getNormalMatrix(src.matrix);
    for (const part of partsOf(g, src.multiMaterial)) {
      const base = positions.length / 3;
      const local = new Map();
      const start = indices.length;
      for (let q = part.start; q < part.end - ((part.end - part.start) % 3); ++q) {
        const v = g.index ? g.index.getX(q) : q;
        let i = local.get(v);
        if (i === undefined) {
          i = base + local.size;
          local.set(v, i);
          p.fromBufferAttribute(a.position, v).applyMatrix4(src.matrix);
          positions.push(p.x, p.y, p.z);
          p.fromBufferAttribute(a.normal, v).applyMatrix3(normalMatrix).normalize();
          normals.push(p.x, p.y, p.z);
          for (let k = 0; k < uvSets; ++k) {
            const uv = a[uvNames[k]];
            // three's uv has v up, glTF's v down (restitch keeps glTF's): flipped here and back.
            uvs[k].push(uv ? uv.getX(v) : 0, uv ? 1 - uv.getY(v) : 0);
          }
          if (anyColor) {
            const c = a.color;
            colors.push(c ? c.getX(v) : 1, c ? c.getY(v) : 1, c ? c.getZ(v) : 1, c && c.itemSize === 4 ? c.getW(v) : 1);
          }
        }
        indices.push(i);
      }
      groups.push({ start, count: indices.length - start, material: parts.length, name: `${src.name || 'mesh ' + s} slot ${part.materialIndex}` });
      parts.push({ source: s, materialIndex: part.materialIndex });
    }
  });
  const arrays = {
    positions: new Float32Array(positions), indices: new Uint32Array(indices), normals: new Float32Array(normals),
    uvs: uvs.map((u) => new Float32Array(u)), groups,
  };
  if (anyColor) arrays.colors = new Float32Array(colors);
  return { arrays, parts };
}

// Per source, a new BufferGeometry from its parts of the result mesh, in the source's own frame.
function scatter(mesh, parts, sources) {
  const perSource = sources.map(() => []);
  for (const g of mesh.groups) perSource[parts[g.group].source].push({ ...g, materialIndex: parts[g.group].materialIndex });
  return sources.map((src, s) => {
    const back = new Matrix4().copy(src.matrix).invert();
    const normalBack = new Matrix3().getNormalMatrix(back);
    const remap = new Map();
    const index = [];
    const geometry = new BufferGeometry();
    for (const g of perSource[s]) {
      const start = index.length;
      for (let q = g.start; q < g.start + g.count; ++q) {
        const v = mesh.indices[q];
        let i = remap.get(v);
        if (i === undefined) remap.set(v, (i = remap.size));
        index.push(i);
      }
      if (src.multiMaterial) geometry.addGroup(start, index.length - start, g.materialIndex);
    }
    const n = remap.size;
    const pos = new Float32Array(3 * n);
    const nrm = src.had.normal ? new Float32Array(3 * n) : null;
    const uv = src.had.uvs.map(() => new Float32Array(2 * n));
    const col = src.had.color ? new Float32Array(src.had.color * n) : null;
    const p = new Vector3();
    for (const [v, i] of remap) {
      p.fromArray(mesh.positions, 3 * v).applyMatrix4(back).toArray(pos, 3 * i);
      if (nrm) p.fromArray(mesh.normals, 3 * v).applyMatrix3(normalBack).normalize().toArray(nrm, 3 * i);
      src.had.uvs.forEach((k, j) => {
        uv[j][2 * i] = mesh.uvSets[k][2 * v];
        uv[j][2 * i + 1] = 1 - mesh.uvSets[k][2 * v + 1];
      });
      for (let c = 0; col && c < src.had.color; ++c) col[src.had.color * i + c] = mesh.colors[4 * v + c];
    }
    geometry.setAttribute('position', new BufferAttribute(pos, 3));
    if (nrm) geometry.setAttribute('normal', new BufferAttribute(nrm, 3));
    src.had.uvs.forEach((k, j) => geometry.setAttribute(uvNames[k], new BufferAttribute(uv[j], 2)));
    if (col) geometry.setAttribute('color', new BufferAttribute(col, src.had.color));
    geometry.setIndex(new BufferAttribute(n > 65535 ? new Uint32Array(index) : new Uint16Array(index), 1));
    geometry.computeBoundingBox();
    geometry.computeBoundingSphere();
    return geometry;
  });
}

/** A three.js object (or geometry) with its analysis: resize it as often as wanted. */
export class Resizable {
  #model;
  #parts;
  #sources;
  #results = null;  // the geometries of the last in-place resize

  constructor(target, model, parts, sources) {
    this.target = target;
    this.#model = model;
    this.#parts = parts;
    this.#sources = sources;
    /** What `restitch analyze --json` prints, in the target's local units. */
    this.analysis = model.analysis;
  }

  /** The principal offsets ([x, y, z], target's local units): what `steps` step along, in order. */
  get principalOffsets() {
    return this.#model.principalOffsets;
  }

  /**
   * Resizes (options as restitch's Model.resize: steps or size, exact, pivot, labelSpace, seamEnergy).
   * In place by default: returns the report. With `into: 'new'`: {object, report}, the target untouched.
   */
  resize(options = {}) {
    const result = this.#model.resize(options);
    const geometries = scatter(result.mesh, this.#parts, this.#sources);
    if (options.into === 'new') return { object: this.#copy(geometries), report: result.report };
    if (options.into !== undefined && options.into !== 'self') throw new RestitchError('invalid_argument', "into is 'self' or 'new'");
    this.#place(geometries);
    return result.report;
  }

  /** Puts the original geometries back (an in-place resize can be undone this way). */
  restore() {
    this.#place(null);
  }

  /** Restores the target and frees the analysis' WebAssembly memory; `analyze` again to resize. */
  dispose() {
    this.restore();
    this.#model.delete();
    cache.delete(this.target);
  }

  #place(geometries) {
    const previous = this.#results;
    if (this.target.isBufferGeometry) {
      this.target.copy(geometries ? geometries[0] : this.#sources[0].original);
      this.target.userData = this.#sources[0].userData;
    } else {
      this.#sources.forEach((s, i) => { s.mesh.geometry = geometries ? geometries[i] : s.original; });
    }
    this.#results = this.target.isBufferGeometry ? null : geometries;
    if (geometries && this.target.isBufferGeometry) geometries[0].dispose();
    if (previous) previous.forEach((g) => g.dispose());
  }

  #copy(geometries) {
    if (this.target.isBufferGeometry) return geometries[0];
    const saved = this.#sources.map((s) => s.mesh.geometry);
    this.#sources.forEach((s) => { s.mesh.geometry = s.original; });
    const clone = this.target.clone();
    this.#sources.forEach((s, i) => { s.mesh.geometry = saved[i]; });
    meshesOf(clone).forEach((m, i) => { m.geometry = geometries[i]; });
    return clone;
  }
}

/**
 * Analyses `target` (a BufferGeometry, Mesh or Object3D) and returns its Resizable, cached for the target.
 * Options: descriptor, matcher, detector (policy names), onProgress(stage, fraction), restitch (a Restitch
 * from init(), to use one you made); labelSpace, seamEnergy and prepare (default true): the resize caches
 * for those policies are built here, so the first slider move costs what later ones do.
 */
export async function analyze(target, options = {}) {
  const known = cache.get(target);
  if (known) return known;
  const restitch = await restitchModule(options);
  let sources;
  if (target && target.isBufferGeometry) {
    sources = [{ geometry: target, matrix: new Matrix4(), multiMaterial: target.groups.length > 0, original: target.clone(), userData: target.userData }];
  } else if (target && target.isObject3D) {
    target.updateMatrixWorld(true);
    const rootInverse = new Matrix4().copy(target.matrixWorld).invert();
    sources = meshesOf(target).map((m) => ({
      mesh: m, geometry: m.geometry, original: m.geometry,
      matrix: new Matrix4().multiplyMatrices(rootInverse, m.matrixWorld),
      multiMaterial: Array.isArray(m.material),
    }));
    if (sources.length === 0) throw new RestitchError('invalid_argument', 'the object has no mesh to resize');
  } else {
    throw new RestitchError('invalid_argument', 'analyze() takes a three.js BufferGeometry, Mesh or Object3D');
  }
  for (const s of sources) {
    const a = s.geometry.attributes;
    s.had = { normal: !!a.normal, uvs: uvNames.map((n, k) => (a[n] ? k : -1)).filter((k) => k >= 0), color: a.color ? a.color.itemSize : 0 };
  }
  const { arrays, parts } = gather(sources);
  const model = restitch.fromArrays(arrays);
  try {
    model.analyze(options);
    // The first resize then costs what later ones do (caches built, code paths warm).
    if (model.principalOffsets.length > 0 && options.prepare !== false) model.prepare(options);
  } catch (e) {
    model.delete();
    throw e;
  }
  const resizable = new Resizable(target, model, parts, sources);
  cache.set(target, resizable);
  return resizable;
}

/** analyze(target) (cached) then resize(options): the one call a slider needs. */
export async function resize(target, options = {}) {
  return (await analyze(target, options)).resize(options);
}

/** Forgets the cached analysis of `target` and frees its memory (the target is restored). */
export function release(target) {
  const known = cache.get(target);
  if (known) known.dispose();
}
