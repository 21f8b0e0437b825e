// Typings of restitch/three (three.js). three is a peer dependency.
import type { BufferGeometry, Object3D } from 'three';
import type { AnalyzeOptions, Analysis, Report, ResizeOptions, Restitch, Vec3 } from './index.js';

export interface ThreeAnalyzeOptions extends AnalyzeOptions {
  /** A Restitch from init() to use (default: one shared module instance). */
  restitch?: Restitch;
  /** Build the resize caches during analyze (default true) for these policies, so the first move is fast. */
  prepare?: boolean;
  labelSpace?: string;
  seamEnergy?: string;
}

export interface ThreeResizeOptions extends ResizeOptions {
  /** 'self' (default): replace the target's geometries; 'new': return a resized copy. */
  into?: 'self' | 'new';
}

export type Target = Object3D | BufferGeometry;

export class Resizable<T extends Target = Target> {
  readonly target: T;
  readonly analysis: Analysis;
  readonly principalOffsets: Vec3[];
  resize(options: ThreeResizeOptions & { into?: 'self' }): Report;
  resize(options: ThreeResizeOptions & { into: 'new' }): { object: T; report: Report };
  restore(): void;
  dispose(): void;
}

export function analyze<T extends Target>(target: T, options?: ThreeAnalyzeOptions): Promise<Resizable<T>>;
export function resize<T extends Target>(target: T, options: ThreeAnalyzeOptions & ThreeResizeOptions & { into?: 'self' }): Promise<Report>;
export function resize<T extends Target>(target: T, options: ThreeAnalyzeOptions & ThreeResizeOptions & { into: 'new' }): Promise<{ object: T; report: Report }>;
export function release(target: Target): void;
