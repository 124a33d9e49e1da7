// sinew view: the page. Loads the scene from the server, draws frames that sinew's
// compiled program evaluated, plays them at the rig's fps, edits attributes through the
// lazy graph, and reloads when the server says the rig changed (server-sent events).
// `window.sinew` exposes the page's state for tests and the console.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls.js';
import { Drawing } from '/draw.js';
import * as P from '/panels.js';

const $ = P.$;
const state = window.sinew = {
  ready: false, revision: -1, scene: null, nodes: [], selected: null, frame: 1, start: 1, end: 1, fps: 24,
  playing: false, buffer: null, errorNodes: new Set(), evalErrors: [], loadErrors: null, lastEdit: null,
  framesShown: 0, rate: 0, evalUs: 0, errors: window.__errors,
};

// Three.js: renderer, camera, orbit/pan/zoom, grid and axes.
const viewport = $('viewport');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
viewport.appendChild(renderer.domElement);
const scene3 = new THREE.Scene();
scene3.background = new THREE.Color(0x3a3a3a);
const camera = new THREE.PerspectiveCamera(45, 1, 0.001, 1000);
camera.position.set(3, 2, 4);
const controls = new OrbitControls(camera, renderer.domElement);
scene3.add(new THREE.HemisphereLight(0xffffff, 0x444444, 2.5));
const sun = new THREE.DirectionalLight(0xffffff, 1.5);
sun.position.set(3, 5, 4);
scene3.add(sun);
let grid = null;
const axes = new THREE.AxesHelper(1);
scene3.add(axes);
let drawing = null;

function resize() {
  const w = viewport.clientWidth, h = viewport.clientHeight;
  renderer.setSize(w, h);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);

function frameAll() {
  if (!drawing) return;
  const box = drawing.bounds();
  if (box.isEmpty()) return;
  const c = box.getCenter(new THREE.Vector3());
  const r = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-3);
  const dir = camera.position.clone().sub(controls.target).normalize();
  controls.target.copy(c);
  camera.position.copy(c).addScaledVector(dir, r / Math.sin(camera.fov * Math.PI / 360) * 1.1);
  camera.near = r / 100; camera.far = r * 100;
  camera.updateProjectionMatrix();
  controls.update();
}
state.frameAll = frameAll;

async function fetchFrame(f) {
  const r = await fetch(`/api/frame?f=${f}`);
  if (!r.ok) return null;
  state.evalUs = Number(r.headers.get('X-Eval-Us'));
  const nerr = Number(r.headers.get('X-Eval-Errors'));
  state.evalErrors = nerr > 0 ? await (await fetch('/api/errors')).json() : [];
  return r.arrayBuffer();
}

function applyErrors() {
  state.errorNodes = new Set(state.evalErrors.map((e) => e.node));
  if (drawing) drawing.highlight(state.selected, state.errorNodes);
  P.renderOverlay(state.loadErrors, state.evalErrors);
}

let inFlight = false;
/// Shows frame `f`: the server evaluates the compiled program, the page draws it.
async function showFrame(f) {
  inFlight = true;
  try {
    const buf = await fetchFrame(f);
    if (buf && drawing) {
      state.buffer = buf;
      state.frame = f;
      drawing.update(buf);
      state.framesShown++;
      applyErrors();
    }
    $('scrub').value = state.frame;
    $('frameLabel').textContent = `frame ${state.frame}`;
  } finally { inFlight = false; }
}
state.setFrame = (f) => showFrame(Number(f));

/// Loads (or reloads) the scene; keeps camera, selection, frame and edits.
async function loadScene() {
  const s = await (await fetch('/api/scene')).json();
  state.revision = s.revision;
  state.loadErrors = s.loadErrors;
  $('rig').textContent = s.rig;
  if (!s.scene) { applyErrors(); state.ready = true; return; }
  const first = !state.scene;
  state.scene = s.scene; state.nodes = s.nodes; state.fps = s.fps; state.start = s.start; state.end = s.end;
  state.edits = s.edits;
  if (first) state.frame = s.frame;
  state.frame = Math.min(Math.max(state.frame, s.start), s.end);
  $('scrub').min = s.start; $('scrub').max = s.end;
  $('start').textContent = s.start; $('end').textContent = s.end;
  const buf = await fetchFrame(state.frame);
  if (drawing) drawing.dispose();
  drawing = new Drawing(scene3);
  drawing.build(s.scene, buf);
  state.drawing = drawing;
  state.buffer = buf;
  drawing.update(buf);
  state.jointCount = s.scene.items.filter((i) => i.kind === 'joint').length;
  if (first) {
    const box = drawing.bounds();
    const size = box.isEmpty() ? 1 : box.getSize(new THREE.Vector3()).length();
    const step = Math.pow(10, Math.round(Math.log10(size / 10)));
    grid = new THREE.GridHelper(step * 40, 40, 0x666666, 0x4a4a4a);
    scene3.add(grid);
    axes.scale.setScalar(step * 2);
    frameAll();
  }
  $('status').textContent = `${s.nodes.length} nodes · ${state.jointCount} joints · ${s.scene.meshes.length} meshes · loaded in ${s.loadMs.toFixed(1)} ms`;
  applyErrors();
  P.renderNodeList(state, select);
  if (state.selected && !state.nodes.some((n) => n.name === state.selected)) state.selected = null;
  if (state.selected) await select(state.selected); else P.renderGraph(null, select);
  state.ready = true;
}
state.reload = loadScene;

/// Selects a node: attribute panel, graph panel, highlight.
async function select(name) {
  state.selected = name;
  P.renderNodeList(state, select);
  if (drawing) drawing.highlight(name, state.errorNodes);
  const r = await fetch(`/api/node?name=${encodeURIComponent(name)}`);
  if (r.ok) P.renderAttrs(await r.json(), setAttr);
  await P.renderGraph(name, select);
}
state.select = select;

/// Sets a plug through the lazy graph, then redraws the current frame.
async function setAttr(plug, text) {
  const r = await fetch('/api/set', { method: 'POST', body: JSON.stringify({ plug, value: text }) });
  const body = await r.json();
  if (!r.ok) { state.lastEdit = body; console.warn(body.error); return body; }
  state.lastEdit = body;
  P.showEditStats(body);
  await showFrame(state.frame);
  return body;
}
state.setAttr = setAttr;

// Picking: a click (not a drag) on a joint, control or marker selects it.
const ray = new THREE.Raycaster();
let down = null;
renderer.domElement.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
renderer.domElement.addEventListener('pointerup', (e) => {
  if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4 || !drawing) return;
  const rect = renderer.domElement.getBoundingClientRect();
  const p = new THREE.Vector2((e.clientX - rect.left) / rect.width * 2 - 1, -(e.clientY - rect.top) / rect.height * 2 + 1);
  ray.setFromCamera(p, camera);
  const hit = ray.intersectObjects(drawing.pickables, false)[0];
  if (hit) select(hit.object.userData.name);
});
state.screenPosition = (name) => drawing?.screenPosition(name, camera, renderer.domElement.clientWidth, renderer.domElement.clientHeight);

// Timeline: play at the rig's fps (frames the server cannot keep up with are skipped).
let playStart = 0, playFrom = 1;
function setPlaying(on) {
  state.playing = on;
  $('play').textContent = on ? '⏸' : '▶';
  playStart = performance.now(); playFrom = state.frame;
}
state.setPlaying = setPlaying;
$('play').onclick = () => setPlaying(!state.playing);
$('prev').onclick = () => { setPlaying(false); showFrame(state.frame > state.start ? state.frame - 1 : state.end); };
$('next').onclick = () => { setPlaying(false); showFrame(state.frame < state.end ? state.frame + 1 : state.start); };
$('scrub').oninput = () => { setPlaying(false); showFrame(Number($('scrub').value)); };
$('frameAll').onclick = frameAll;
$('search').oninput = () => P.renderNodeList(state, select);
window.addEventListener('keydown', (e) => {
  if (e.target.tagName === 'INPUT') return;
  if (e.key === ' ') { e.preventDefault(); setPlaying(!state.playing); }
  if (e.key === 'f') frameAll();
});
document.querySelectorAll('#tabs button').forEach((b) => {
  b.onclick = () => {
    document.querySelectorAll('#tabs button').forEach((x) => x.classList.toggle('on', x === b));
    document.querySelectorAll('.tab').forEach((t) => { t.hidden = t.id !== b.dataset.tab; });
  };
});
$('runProfile').onclick = async () => {
  const r = await fetch('/api/profile');
  const p = await r.json();
  if (r.ok) { state.profile = p; P.renderProfile(p); if (state.selected) P.renderGraph(state.selected, select); }
};

let rateCount = 0, rateT0 = performance.now();
function tick(now) {
  requestAnimationFrame(tick);
  if (state.playing && !inFlight && state.scene) {
    const len = state.end - state.start + 1;
    const f = state.start + ((Math.floor((now - playStart) / 1000 * state.fps) + (playFrom - state.start)) % len);
    if (f !== state.frame) { rateCount++; showFrame(f); }
  }
  if (now - rateT0 > 1000) {
    state.rate = rateCount * 1000 / (now - rateT0);
    rateCount = 0; rateT0 = now;
    $('rate').textContent = `${state.playing ? state.rate.toFixed(1) + ' fps · ' : ''}eval ${state.evalUs.toFixed(0)} µs · ${state.fps} fps rig`;
  }
  controls.update();
  renderer.render(scene3, camera);
}

// Hot reload: the server sends `reload` when a file the rig uses changed.
function listen() {
  const es = new EventSource('/api/events');
  es.addEventListener('reload', () => loadScene());
}

resize();
await loadScene();
listen();
requestAnimationFrame(tick);
