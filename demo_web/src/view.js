// view.js - the 3D view: renderer, scene, camera framing and the histogram inset; draws on demand.
//
//   const view = new View({ container, histogramLabel, insets, showHistogram });
//   view.modelGroup / view.seamGroup / view.arrowGroup / view.histGroup   what the app fills (./layers.js)
//   view.render()                 draws the scene (and the histogram inset when showHistogram() says so)
//   view.fitCamera(box)           frames a box from the default direction (a new model)
//   view.followBox(box)           frames a resized model keeping the user's direction, pan and zoom
//   view.getCamera() / view.setCamera({position, target})   model units
//   view.histogramToScreen([x, y, z]) -> {x, y} | null   where a point of the histogram inset (normalized units)
//                                 was last drawn, in CSS pixels from the canvas's top left (null: inset hidden)
// `insets()` returns the widths {left, right} of the page's overlays: the projection is centred between them
// and a box is framed to fit there. Orbiting and window resizes redraw by themselves; nothing animates
// otherwise, so every change of the groups must be followed by render().
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';

const HIST_SIZE = 240;  // the histogram inset, in CSS pixels, bottom left
const HIST_MARGIN = 8;

export class View {
  modelGroup = new THREE.Group();   // the model shown (input or result)
  arrowGroup = new THREE.Group();   // principal offsets on the model (paper Fig. 2)
  seamGroup = new THREE.Group();    // seam faces between differently labelled cells
  histGroup = new THREE.Group();    // the histogram inset's content, in normalized units

  #framed = null;  // the framing of the box shown last: resized models keep the user's pan and zoom relative to it

  constructor({ container, histogramLabel, insets = () => ({ left: 0, right: 0 }), showHistogram = () => false }) {
    this.histogramLabel = histogramLabel;
    this.insets = insets;
    this.showHistogram = showHistogram;
    const renderer = new THREE.WebGLRenderer({ antialias: true });
    renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    renderer.setSize(window.innerWidth, window.innerHeight);
    renderer.autoClear = false;
    container.appendChild(renderer.domElement);
    this.renderer = renderer;

    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x2a2d33);
    this.scene.environment = new THREE.PMREMGenerator(renderer).fromScene(new RoomEnvironment(), 0.04).texture;
    this.scene.environmentIntensity = 0.7;
    const sun = new THREE.DirectionalLight(0xffffff, 0.9);
    sun.position.set(1, 2, 3);
    this.scene.add(sun, this.modelGroup, this.arrowGroup, this.seamGroup);

    this.camera = new THREE.PerspectiveCamera(40, window.innerWidth / window.innerHeight, 0.001, 1000);
    this.controls = new OrbitControls(this.camera, renderer.domElement);
    this.controls.addEventListener('change', () => this.render());

    this.#warmUp();

    this.histScene = new THREE.Scene();
    this.histScene.background = new THREE.Color(0x16181c);
    this.histCamera = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
    this.histScene.add(this.histGroup, new THREE.AxesHelper(0.5));

    window.addEventListener('resize', () => {
      this.camera.aspect = window.innerWidth / window.innerHeight;
      this.camera.updateProjectionMatrix();
      this.renderer.setSize(window.innerWidth, window.innerHeight);
      this.render();
    });
  }

  // Compiles, before any result is drawn, the shader programs the first resize result adds (the seam
  // overlay: transparent double-sided faces and lines), so the first slider move does not wait for them.
  // three.js keys programs by material kind and parameters, so stand-ins of the same kinds are enough.
  #warmUp() {
    const group = new THREE.Group();
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute([0, 0, 0, 1, 0, 0, 0, 1, 0], 3));
    const materials = [
      new THREE.MeshBasicMaterial({ transparent: true, opacity: 0.5, side: THREE.DoubleSide, depthWrite: false }),
      new THREE.LineBasicMaterial(),
      new THREE.MeshStandardMaterial({ vertexColors: true, side: THREE.DoubleSide }),
    ];
    group.add(new THREE.Mesh(geometry, materials[0]), new THREE.LineSegments(geometry, materials[1]),
              new THREE.Mesh(geometry, materials[2]));
    this.scene.add(group);
    this.renderer.compile(this.scene, this.camera);
    this.scene.remove(group);
    geometry.dispose();  // the materials are kept: disposing them would release their programs
  }

  render() {
    const { renderer, camera } = this;
    const w = window.innerWidth, h = window.innerHeight;
    this.#updateViewOffset();
    renderer.setViewport(0, 0, w, h);
    renderer.setScissorTest(false);
    renderer.clear();
    renderer.render(this.scene, camera);
    const histogram = this.showHistogram();
    if (histogram) {
      const dir = camera.position.clone().sub(this.controls.target).normalize();
      this.histCamera.position.copy(dir.multiplyScalar(6.5));
      this.histCamera.up.copy(camera.up);
      this.histCamera.lookAt(0, 0, 0);
      renderer.setScissorTest(true);
      renderer.setScissor(HIST_MARGIN, HIST_MARGIN, HIST_SIZE, HIST_SIZE);
      renderer.setViewport(HIST_MARGIN, HIST_MARGIN, HIST_SIZE, HIST_SIZE);
      renderer.clear();
      renderer.render(this.histScene, this.histCamera);
      renderer.setScissorTest(false);
    }
    this.histogramLabel.hidden = !histogram;
  }

  histogramToScreen(p) {
    if (!this.showHistogram()) return null;
    const v = new THREE.Vector3(...p).project(this.histCamera);
    if (Math.abs(v.x) > 1 || Math.abs(v.y) > 1) return null;
    const h = this.renderer.domElement.clientHeight;
    return { x: HIST_MARGIN + (v.x + 1) / 2 * HIST_SIZE, y: h - HIST_MARGIN - (v.y + 1) / 2 * HIST_SIZE };
  }

  // The box of what a group shows, in model units.
  boxOf(group) {
    return new THREE.Box3().setFromObject(group);
  }

  fitCamera(box) {
    const { camera, controls } = this;
    const framed = this.#framing(box);
    this.#framed = framed;
    camera.position.copy(framed.center).add(new THREE.Vector3(0.35, 0.3, 1).normalize().multiplyScalar(framed.dist));
    camera.near = framed.dist / 100;
    camera.far = framed.dist * 100;
    camera.updateProjectionMatrix();
    controls.target.copy(framed.center);
    controls.update();
  }

  // Follows a resized model: same view direction, pan and zoom relative to its new bounding box.
  followBox(box) {
    if (!this.#framed) return this.fitCamera(box);
    const { camera, controls } = this;
    const framed = this.#framed, next = this.#framing(box);
    const offset = camera.position.clone().sub(controls.target);
    const zoom = offset.length() / framed.dist;
    const pan = controls.target.clone().sub(framed.center).multiplyScalar(next.dist / framed.dist);
    controls.target.copy(next.center).add(pan);
    camera.position.copy(controls.target).add(offset.setLength(next.dist * zoom));
    camera.near = next.dist / 100;
    camera.far = next.dist * 100;
    camera.updateProjectionMatrix();
    controls.update();
    this.#framed = next;
  }

  getCamera() {
    return { position: this.camera.position.toArray(), target: this.controls.target.toArray() };
  }

  setCamera({ position, target }) {
    this.controls.target.fromArray(target);
    this.camera.position.fromArray(position);
    this.controls.update();
    this.render();
  }

  // The distance at which a box fills the view between the overlays, and its centre.
  #framing(box) {
    const { camera } = this;
    const size = box.getSize(new THREE.Vector3());
    const radius = Math.max(size.length() / 2, 1e-6);
    const free = this.#freeWidth() / window.innerHeight;  // the aspect of the view between the overlays
    const half = THREE.MathUtils.degToRad(camera.fov / 2);
    const fov = Math.min(camera.fov, 2 * THREE.MathUtils.radToDeg(Math.atan(Math.tan(half) * free)));
    return { center: box.getCenter(new THREE.Vector3()), dist: radius / Math.sin(THREE.MathUtils.degToRad(fov / 2)) * 1.1 };
  }

  #freeWidth() {
    const o = this.insets();
    return Math.max(window.innerWidth - o.left - o.right, window.innerWidth * 0.4);
  }

  // Centre the projection between the overlays.
  #updateViewOffset() {
    const w = window.innerWidth, h = window.innerHeight, o = this.insets();
    this.camera.setViewOffset(w, h, -Math.round((o.left - o.right) / 2), 0, w, h);
  }
}
