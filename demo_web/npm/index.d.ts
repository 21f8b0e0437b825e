// Typings of the restitch package (index.js). Field names of Analysis and Report are those of
// `restitch analyze --json` and `restitch resize --json`.

export type Vec3 = [number, number, number];

/** A failure of the library. `code` is its StatusCode name. */
export class RestitchError extends Error {
  readonly name: 'RestitchError';
  readonly code: 'invalid_argument' | 'io_error' | 'parse_error' | 'invalid_mesh' | 'unsupported' | 'no_repetition' | 'too_large' |
    'cancelled' | 'internal' | string;
  constructor(code: string, message: string);
}

export interface InitOptions {
  /** The .wasm bytes, when they are not next to the module (bundlers, offline caches). */
  wasmBinary?: ArrayBuffer | Uint8Array;
  /** A WebAssembly.Memory to use (its maximum caps the module's memory; 2048 MB at most). */
  wasmMemory?: WebAssembly.Memory;
  /** Where to find restitch_web.wasm (Emscripten's locateFile). */
  locateFile?: (path: string, prefix: string) => string;
}

/** Loads the WebAssembly module: one instance, its own memory, per call. */
export function init(options?: InitOptions): Promise<Restitch>;
/** The raw embind module that `init` wraps (Session objects answering {ok, ...}). */
export function loadRestitch(options?: InitOptions): Promise<unknown>;

export interface Policies {
  descriptors: string[];
  matchers: string[];
  detectors: string[];
  label_spaces: string[];
  pivots: string[];
  seam_energies: string[];
}

export interface SampleParameter {
  name: string; value: number; min: number; max: number; integer: boolean; help: string;
}
export interface SampleInfo {
  name: string; description: string; units: string; parameters: SampleParameter[];
}

/** A mesh as arrays (world space, model units). */
export interface MeshArrays {
  positions: Float32Array;
  /** Three indices per triangle, counter-clockwise front faces. */
  indices: Uint32Array;
  normals?: Float32Array;
  /** One Float32Array (u, v per vertex, glTF convention: v down) per texture-coordinate set. */
  uvs?: Float32Array[];
  /** r, g, b, a per vertex, linear. */
  colors?: Float32Array;
  /** Ranges of `indices`, in order, covering them: one material each (-1: none). */
  groups?: { start: number; count: number; material?: number; name?: string }[];
}

/** A mesh the module gives back: faces ordered by group, one draw range per group. */
export interface OutputMesh {
  positions: Float32Array;
  normals?: Float32Array;
  /** The first texture-coordinate set. */
  uvs?: Float32Array;
  /** Every texture-coordinate set, TEXCOORD_0 first. */
  uvSets: Float32Array[];
  colors?: Float32Array;
  indices: Uint32Array;
  /** start and count in indices; `group`: the input group it comes from. */
  groups: { start: number; count: number; material: number; group: number; name: string; colors: boolean }[];
}

export interface ModelInfo {
  vertices: number;
  triangles: number;
  bbox_min: Vec3;
  bbox_max: Vec3;
  warnings: string[];
  /** Samples only: their true repeats. */
  generators?: Vec3[];
}

export interface AnalyzeOptions {
  descriptor?: string;
  matcher?: string;
  detector?: string;
  onProgress?: (stage: string, fraction: number) => void;
}

export interface DominantOffset {
  offset: Vec3;
  votes: number;
  overlap: number;
  significant: boolean;
  promoted: boolean;
  divisor: number;
  rejected_by: string | null;
  tests: { name: string; passed: boolean; value: number; threshold: number; at_most: boolean }[];
}

/** What `restitch analyze --json` prints (model units). */
export interface Analysis {
  descriptor: string;
  matcher: string;
  detector: string;
  features: number;
  scale: number;
  /** What steps step along, in order. */
  principal_offsets: Vec3[];
  dominant_offsets: DominantOffset[];
  /** Repeats found but not made principal: promote() one to resize along it. */
  candidates: { offset: Vec3; [field: string]: unknown }[];
  dummy_directions: Vec3[];
  lattice_axes: Vec3[];
  lattice_cells: Vec3;
  lattice_origin: Vec3;
  resizable: [boolean, boolean, boolean];
  sparsity: { bins: number; top7: number; top20: number };
  timings_ms: Record<string, number>;
  [field: string]: unknown;
}

export interface Seam {
  cells: [Vec3, Vec3];
  labels: [Vec3, Vec3];
  mismatch: number;
  offset: number;
  outer: boolean;
}

/** The result check's finding: check is "open seam", "part count", "size", "floating piece", "side by side", ... */
export interface Warning {
  check: string;
  message: string;
}

/** What `restitch resize --json` prints. */
export interface Report {
  steps: Vec3;
  steps_principal: number[];
  grid_steps: Vec3;
  cells_in: Vec3;
  cells_out: Vec3;
  size_in: Vec3;
  size_out: Vec3;
  exact: { applied: boolean; scale: Vec3; size_nearest: Vec3 };
  pivot: { point: Vec3; translation: Vec3; modes: [string, string, string]; low_end_cells: Vec3 };
  output: { triangles: number; vertices: number };
  boundary_edges: { in: number; out: number; new: number };
  seams: Seam[];
  max_seam_mismatch: number;
  seam_tolerance: number;
  warnings: Warning[];
  label_space: string;
  seam_energy: string;
  timings_ms: Record<string, number>;
  [field: string]: unknown;
}

export interface ResizeOptions {
  /** Whole repeats to add (or remove, negative) along each principal offset, in order. */
  steps?: number | number[];
  /** A bounding-box size [x, y, z] (model units; 0 or null keeps an axis): the nearest whole repeats. */
  size?: [number | null, number | null, number | null] | number[];
  /** With size: scale the nearest whole repeats to the size exactly, about the pivot. */
  exact?: boolean;
  /** What stays put: "origin" (default), "min", "center", "max", or one per axis "min,origin,max". */
  pivot?: string;
  labelSpace?: string;
  seamEnergy?: string;
}

export class Restitch {
  /** "restitch X.Y.Z" */
  readonly version: string;
  policies(): Policies;
  samples(): SampleInfo[];
  /** A model from the bytes of a .glb (or a .gltf with data: URIs). */
  open(bytes: Uint8Array | ArrayBuffer): Model;
  fromArrays(arrays: MeshArrays): Model;
  sample(name: string, params?: Record<string, number>): Model;
}

/** A loaded model; holds WebAssembly memory until delete(). */
export class Model {
  readonly info: ModelInfo;
  /** The last analysis, or null before analyze(). */
  readonly analysis: Analysis | null;
  readonly principalOffsets: Vec3[];
  /** Finds the repeats (synchronous: it blocks the thread, so use a worker for large models in a page). */
  analyze(options?: AnalyzeOptions): Analysis;
  /**
   * Builds the resize caches for these policies and runs one throw-away resize per principal offset, so the
   * first real resize is as fast as later ones. Returns the milliseconds spent.
   */
  prepare(options?: { labelSpace?: string; seamEnergy?: string }): number;
  /** Makes these offsets (at most three, model units) the principal ones; [] goes back to the detected ones. */
  promote(offsets: Vec3[]): Analysis;
  /** Resizes (analysing first with the defaults when not analysed). */
  resize(options: ResizeOptions): Result;
  mesh(): OutputMesh;
  glb(): Uint8Array;
  delete(): void;
}

/** One resize. `glb()` is valid until the model's next resize or delete. */
export class Result {
  readonly report: Report;
  readonly warnings: Warning[];
  readonly mesh: OutputMesh;
  /** The label grid in model units. */
  readonly grid: { axes: [Vec3, Vec3, Vec3]; origin: Vec3 };
  readonly cellLabels: Int32Array;
  readonly labelShifts: Int32Array;
  /** Two corners (x, y, z) per open edge of the result that the input does not have. */
  readonly openEdges: Float32Array;
  glb(): Uint8Array;
}
