// The swim viewer inlined in aquagait's HTML export (src/aquagait/io/export/html.py).
//
// Reads the swim from the page's <script type="application/json" id="aquagait-swim">
// (the format is in html.py's docstring), draws the creature's link meshes and
// the particle traces with three.js, and plays them: play/pause (#play), a scrub
// slider over frames (#scrub), traces shown or not (#traces), an orbit camera.
// World: metres, +z up.
// Bundled into one IIFE by tools/build_viewer.sh; nothing is loaded at run time.
//
// For tests and scripts: window.aquagait = {frame, frames, setFrame(f), play(),
// pause(), project(x, y, z) -> [x, y] CSS pixels from the canvas's top-left, ready}.

import * as THREE from "three";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";

const BACKGROUND = 0xffffff;
const TRACE_COLOUR = [0.1, 0.2, 0.45]; // sRGB, as aquagait's videos draw traces (aquagait.viz.gl)
const FOV = 30; // vertical field of view [deg], as aquagait.viz.camera
const FILL = 0.85; // the share of the picture's half-sides the whole swim may reach
// The direction the camera looks at the start: a 3D swim from behind, beside and above
// (aquagait.viz.camera's 'follow' view); a 2D swim, in the plane z = 0, from above,
// tilted a little towards +y so that the orbit about +z has a well-defined azimuth.
const VIEW_3D = [1, 1, -0.7];
const VIEW_2D = [0, 0.3, -1];

const TYPES = {
  float32: Float32Array,
  uint32: Uint32Array,
  uint16: Uint16Array,
  uint8: Uint8Array,
};

/** A typed array from the payload's {dtype, shape, data: base64 of little-endian bytes}. */
function decode(array) {
  const text = atob(array.data);
  const bytes = new Uint8Array(text.length);
  for (let i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);
  return new TYPES[array.dtype](bytes.buffer);
}

/** sRGB in [0, 1] to linear, the colour space three.js shades in. */
function linear(c) {
  return c <= 0.04045 ? c / 12.92 : Math.pow((c + 0.055) / 1.055, 2.4);
}

function linkMesh(link) {
  const geometry = new THREE.BufferGeometry();
  const rgba = decode(link.colours);
  const colours = new Float32Array(rgba.length);
  let opaque = true;
  for (let i = 0; i < rgba.length; i++) {
    colours[i] = i % 4 === 3 ? rgba[i] / 255 : linear(rgba[i] / 255);
    if (i % 4 === 3 && rgba[i] < 255) opaque = false;
  }
  geometry.setAttribute("position", new THREE.BufferAttribute(decode(link.vertices), 3));
  geometry.setAttribute("normal", new THREE.BufferAttribute(decode(link.normals), 3));
  geometry.setAttribute("color", new THREE.BufferAttribute(colours, 4));
  geometry.setIndex(new THREE.BufferAttribute(decode(link.triangles), 1));
  const material = new THREE.MeshStandardMaterial({
    vertexColors: true,
    roughness: 0.55,
    metalness: 0.0,
    transparent: !opaque,
  });
  return new THREE.Mesh(geometry, material);
}

/** The traces of every frame, and the line segments that draw one frame's. */
class Traces {
  constructor(traces) {
    this.count = traces.count;
    this.length = traces.length;
    this.points = decode(traces.points);
    this.size = decode(traces.size);
    this.alpha = decode(traces.alpha);
    this.fade = decode(traces.fade);
    this.last = traces.last ? decode(traces.last) : null;
    this.stride = traces.stride;
    const vertices = 2 * this.count * Math.max(this.length - 1, 0);
    const geometry = new THREE.BufferGeometry();
    this.position = new THREE.BufferAttribute(new Float32Array(3 * vertices), 3);
    this.colour = new THREE.BufferAttribute(new Float32Array(4 * vertices), 4);
    this.position.setUsage(THREE.DynamicDrawUsage);
    this.colour.setUsage(THREE.DynamicDrawUsage);
    geometry.setAttribute("position", this.position);
    geometry.setAttribute("color", this.colour);
    const material = new THREE.LineBasicMaterial({
      vertexColors: true,
      transparent: true,
      depthWrite: false, // hidden by the body, never by each other
    });
    this.lines = new THREE.LineSegments(geometry, material);
    this.lines.frustumCulled = false;
    this.lines.renderOrder = 1;
  }

  /** Fill the segments with frame f's traces: trace i's newest `size` points, oldest first
   * (position k, k >= length - size, is point last - (length - 1 - k) stride). */
  show(f) {
    const { count, length, points, size, alpha, fade, stride } = this;
    const xyz = this.position.array;
    const rgba = this.colour.array;
    const [r, g, b] = TRACE_COLOUR.map(linear);
    let v = 0;
    for (let i = 0; i < count; i++) {
      const k = f * count + i;
      const n = size[k];
      const last = this.last ? this.last[k] : k;
      const put = (position) => {
        const p = last - (length - 1 - position) * stride;
        xyz[3 * v] = points[3 * p];
        xyz[3 * v + 1] = points[3 * p + 1];
        xyz[3 * v + 2] = points[3 * p + 2];
        rgba[4 * v] = r;
        rgba[4 * v + 1] = g;
        rgba[4 * v + 2] = b;
        rgba[4 * v + 3] = (alpha[p] / 255) * fade[position];
        v++;
      };
      for (let position = length - n + 1; position < length; position++) {
        put(position - 1);
        put(position);
      }
    }
    this.lines.geometry.setDrawRange(0, v);
    this.position.needsUpdate = true;
    this.colour.needsUpdate = true;
  }
}

/** A box [m] around every link at every frame (each link's mesh by its bounding sphere). */
function swimBox(linkPos, linkQuat, meshes) {
  const box = new THREE.Box3();
  const centre = new THREE.Vector3();
  const rotation = new THREE.Quaternion();
  const links = meshes.length;
  for (let k = 0; k < linkPos.length / 3; k++) {
    const geometry = meshes[k % links].geometry;
    if (!geometry.boundingSphere) geometry.computeBoundingSphere();
    const sphere = geometry.boundingSphere;
    if (sphere.radius < 0) continue; // a link without geoms
    rotation.set(linkQuat[4 * k + 1], linkQuat[4 * k + 2], linkQuat[4 * k + 3], linkQuat[4 * k]);
    centre.copy(sphere.center).applyQuaternion(rotation);
    centre.add(new THREE.Vector3(linkPos[3 * k], linkPos[3 * k + 1], linkPos[3 * k + 2]));
    box.expandByPoint(centre.clone().addScalar(sphere.radius));
    box.expandByPoint(centre.clone().addScalar(-sphere.radius));
  }
  return box;
}

/** The distance [m] from the box's centre, along -forward, at which every corner is in sight
 * within FILL of the picture's half-sides (as aquagait.viz.camera.view_camera). */
function framingDistance(box, forward, up, aspect) {
  const right = new THREE.Vector3().crossVectors(forward, up).normalize();
  const screenUp = new THREE.Vector3().crossVectors(right, forward);
  const tanY = FILL * Math.tan(FOV * (Math.PI / 360));
  const half = box.getSize(new THREE.Vector3()).multiplyScalar(0.5);
  let distance = 1e-6;
  for (const sx of [-1, 1]) {
    for (const sy of [-1, 1]) {
      for (const sz of [-1, 1]) {
        const corner = new THREE.Vector3(sx * half.x, sy * half.y, sz * half.z);
        const depth = corner.dot(forward);
        distance = Math.max(
          distance,
          Math.abs(corner.dot(right)) / (tanY * aspect) - depth,
          Math.abs(corner.dot(screenUp)) / tanY - depth,
        );
      }
    }
  }
  return distance;
}

function main() {
  const swim = JSON.parse(document.getElementById("aquagait-swim").textContent);
  const frames = swim.frames;
  const time = decode(swim.time);
  const linkPos = decode(swim.link_pos);
  const linkQuat = decode(swim.link_quat); // (w, x, y, z)
  const links = swim.links.length;

  const renderer = new THREE.WebGLRenderer({ antialias: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.setSize(window.innerWidth, window.innerHeight);
  renderer.setClearColor(BACKGROUND);
  document.body.prepend(renderer.domElement);

  const scene = new THREE.Scene();
  const meshes = swim.links.map(linkMesh);
  for (const mesh of meshes) scene.add(mesh);
  const traces = swim.traces ? new Traces(swim.traces) : null;
  if (traces) scene.add(traces.lines);

  // Lights fixed to the camera, so the side it sees is lit from every view.
  const camera = new THREE.PerspectiveCamera(FOV, window.innerWidth / window.innerHeight);
  camera.up.set(0, 0, 1);
  scene.add(camera);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8899aa, 1.2));
  const key = new THREE.DirectionalLight(0xffffff, 2.0);
  key.position.set(-0.5, 1, 1);
  camera.add(key);

  const box = swimBox(linkPos, linkQuat, meshes);
  const centre = box.getCenter(new THREE.Vector3());
  const view = new THREE.Vector3(...(swim.dim === 2 ? VIEW_2D : VIEW_3D)).normalize();
  const distance = framingDistance(box, view, camera.up, camera.aspect);
  camera.position.copy(centre).addScaledVector(view, -distance);
  camera.near = distance / 50;
  camera.far = distance * 50;
  camera.updateProjectionMatrix();
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.copy(centre);
  controls.update();

  const info = document.getElementById("info");
  const scrub = document.getElementById("scrub");
  const button = document.getElementById("play");
  const showTraces = document.getElementById("traces");
  scrub.max = String(frames - 1);
  showTraces.disabled = !traces;

  let frame = 0;
  const render = () => renderer.render(scene, camera);
  controls.addEventListener("change", render);

  function setFrame(f) {
    frame = Math.min(Math.max(Math.round(f), 0), frames - 1);
    for (let l = 0; l < links; l++) {
      const p = 3 * (frame * links + l);
      const q = 4 * (frame * links + l);
      meshes[l].position.set(linkPos[p], linkPos[p + 1], linkPos[p + 2]);
      meshes[l].quaternion.set(linkQuat[q + 1], linkQuat[q + 2], linkQuat[q + 3], linkQuat[q]);
    }
    if (traces) traces.show(frame);
    scrub.value = String(frame);
    const now = `t = ${time[frame].toFixed(2)} s`;
    info.textContent = `${swim.name}   ${now}   frame ${frame} / ${frames - 1}`;
    render();
  }

  // Playback: the frame shown is the one due at the wall-clock time since play().
  let playing = false;
  let started = 0;
  let startFrame = 0;
  function tick(now) {
    if (!playing) return;
    const due = (startFrame + Math.floor(((now - started) / 1000) * swim.fps)) % frames;
    if (due !== frame) setFrame(due);
    requestAnimationFrame(tick);
  }
  function play() {
    if (playing) return;
    playing = true;
    started = performance.now();
    startFrame = frame === frames - 1 ? 0 : frame;
    button.textContent = "Pause";
    requestAnimationFrame(tick);
  }
  function pause() {
    playing = false;
    button.textContent = "Play";
  }

  button.addEventListener("click", () => (playing ? pause() : play()));
  showTraces.addEventListener("change", () => {
    if (traces) traces.lines.visible = showTraces.checked;
    render();
  });
  scrub.addEventListener("input", () => {
    pause();
    setFrame(Number(scrub.value));
  });
  window.addEventListener("keydown", (event) => {
    const target = event.target; // a focused button or slider handles its own keys
    if (target instanceof HTMLInputElement || target instanceof HTMLButtonElement) return;
    if (event.key === " ") playing ? pause() : play();
    else if (event.key === "ArrowRight") setFrame(frame + 1);
    else if (event.key === "ArrowLeft") setFrame(frame - 1);
    else return;
    event.preventDefault();
  });
  window.addEventListener("resize", () => {
    renderer.setSize(window.innerWidth, window.innerHeight);
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    render();
  });

  function project(x, y, z) {
    camera.updateMatrixWorld();
    const ndc = new THREE.Vector3(x, y, z).project(camera);
    const canvas = renderer.domElement;
    return [((ndc.x + 1) / 2) * canvas.clientWidth, ((1 - ndc.y) / 2) * canvas.clientHeight];
  }

  setFrame(0);
  window.aquagait = {
    get frame() {
      return frame;
    },
    frames,
    setFrame,
    play,
    pause,
    project,
    ready: true,
  };
}

try {
  main();
} catch (error) {
  document.getElementById("info").textContent = `The swim cannot be shown: ${error.message}`;
  throw error;
}
