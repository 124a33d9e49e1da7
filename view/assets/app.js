// sinew view: the page. Loads the scene from the server, draws frames that sinew's
// compiled program evaluated, plays them at the rig's fps, edits attributes through the
// lazy graph, and reloads when the server says the rig changed (server-sent events).
// `window.sinew` exposes the page's state for tests and the console.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls.js';
import { Drawing } from '/draw.js';
import * as P from '/panels.js';

const $ = P.$;
/// Milliseconds since the Unix epoch (comparable with the server's and the tests' clocks).
const epochMs = () => performance.timeOrigin + performance.now();
const state = window.sinew = {
  ready: false, revision: -1, scene: null, sceneKey: null, nodes: [], selected: null, frame: 1, start: 1, end: 1,
  fps: 24, playing: false, buffer: null, problems: [], problemNodes: new Map(), loadErrors: null, lastEdit: null,
  framesShown: 0, renders: 0, rate: 0, evalUs: 0, errors: window.__errors, profile: null,
  drawnRevision: -1, panelsRevision: -1, graphCenter: null, reloads: [],
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
window.addEventListener('resize', () => { resize(); invalidate(); });

// Drawing on demand: an animation frame renders only when something drawn changed (a
// frame, the camera, a highlight, the size), so an idle viewer costs no CPU.
let needsRender = true;
function invalidate() { needsRender = true; }
controls.addEventListener('change', invalidate);

function render() {
  controls.update();
  renderer.render(scene3, camera);
  state.renders++;
  needsRender = false;
}

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
  invalidate();
}
state.frameAll = frameAll;

/// Fetches frame `f` evaluated by the server: its buffer, the evaluation time and the
/// revision it belongs to; the frame's problems are fetched when there are any.
async function fetchFrame(f) {
  const r = await fetch(`/api/frame?f=${f}`);
  if (!r.ok) return null;
  const evalUs = Number(r.headers.get('X-Eval-Us'));
  const revision = Number(r.headers.get('X-Revision'));
  const nproblems = Number(r.headers.get('X-Eval-Errors'));
  const [buf, problems] = await Promise.all([
    r.arrayBuffer(), nproblems > 0 ? fetch('/api/errors').then((x) => x.json()) : Promise.resolve([])]);
  return { buf, evalUs, revision, problems };
}

function applyProblems() {
  state.problemNodes = new Map(state.problems.filter((p) => p.node).map((p) => [p.node, p.kind]));
  if (drawing) drawing.highlight(state.selected, state.problemNodes);
  invalidate();
  P.renderOverlay(state.loadErrors, state.problems);
  P.markNodeList(state);
}

/// Draws a fetched frame (the scene must be built).
function showBuffer(fr, f) {
  state.buffer = fr.buf;
  state.frame = f;
  state.evalUs = fr.evalUs;
  state.problems = fr.problems;
  drawing.update(fr.buf);
  invalidate();
  state.framesShown++;
  applyProblems();
  $('scrub').value = state.frame;
  $('frameLabel').textContent = `frame ${state.frame}`;
}

let inFlight = false;
/// Shows frame `f`: the server evaluates the compiled program, the page draws it.
async function showFrame(f) {
  inFlight = true;
  try {
    const fr = await fetchFrame(f);
    if (fr && drawing) showBuffer(fr, f);
  } finally { inFlight = false; }
}
state.setFrame = (f) => showFrame(Number(f));

/// Loads (or reloads) the scene; keeps camera, selection, frame and edits. `timing` (a
/// reload event's data) gets the page's own times: when the scene and the frame arrived,
/// when the scene was redrawn, when the panels were done (epoch milliseconds).
async function loadScene(timing) {
  const t = timing || {};
  t.receivedAt = t.receivedAt || epochMs();
  const first = !state.scene;
  // On a reload the frame to show is known: fetch it with the scene.
  const [s, early] = await Promise.all([
    fetch('/api/scene').then((r) => r.json()),
    first ? Promise.resolve(null) : fetchFrame(state.frame)]);
  t.sceneAt = epochMs();
  state.revision = s.revision;
  state.loadErrors = s.loadErrors;
  $('rig').textContent = s.rig;
  if (!s.scene) { applyProblems(); finishReload(t, s.revision); state.ready = true; return; }
  state.nodes = s.nodes; state.fps = s.fps; state.start = s.start; state.end = s.end;
  state.edits = s.edits;
  if (first) state.frame = s.frame;
  state.frame = Math.min(Math.max(state.frame, s.start), s.end);
  let fr = early;
  if (!fr || fr.revision !== s.revision || first) fr = await fetchFrame(state.frame);
  t.frameAt = epochMs();
  if (!fr) return;
  // The same drawn things as before (a reload that changed values only): keep the objects.
  if (!drawing || s.sceneKey !== state.sceneKey) {
    if (drawing) drawing.dispose();
    drawing = new Drawing(scene3);
    drawing.build(s.scene, fr.buf);
    state.drawing = drawing;
  }
  state.scene = s.scene; state.sceneKey = s.sceneKey;
  showBuffer(fr, state.frame);
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
  render();
  t.drawnAt = epochMs();
  state.drawnRevision = s.revision;
  $('scrub').min = s.start; $('scrub').max = s.end;
  $('start').textContent = s.start; $('end').textContent = s.end;
  $('status').textContent = `${s.nodes.length} nodes · ${state.jointCount} joints · ${s.scene.meshes.length} meshes · loaded in ${s.loadMs.toFixed(1)} ms`;
  P.renderNodeList(state, select);
  if (state.selected && !state.nodes.some((n) => n.name === state.selected)) state.selected = null;
  if (state.selected) await select(state.selected); else await P.renderGraph(null, select);
  finishReload(t, s.revision);
  state.ready = true;
}
state.reload = loadScene;

function finishReload(t, revision) {
  t.panelsAt = epochMs();
  t.pageRevision = revision;
  state.panelsRevision = revision;
  if (t.eventAt !== undefined) state.reloads.push(t);
}

/// Selects a node: attribute panel, graph panel, highlight.
async function select(name) {
  state.selected = name;
  P.renderNodeList(state, select);
  if (drawing) drawing.highlight(name, state.problemNodes);
  invalidate();
  const [r] = await Promise.all([fetch(`/api/node?name=${encodeURIComponent(name)}`), P.renderGraph(name, select)]);
  if (r.ok) P.renderAttrs(await r.json(), setAttr);
  state.graphCenter = name;
}
state.select = select;

/// Sets a plug through the lazy graph, then redraws the current frame.
async function setAttr(plug, text) {
  const r = await fetch('/api/set', { method: 'POST', body: JSON.stringify({ plug, value: text }) });
  const body = await r.json();
  if (!r.ok) { state.lastEdit = body; console.warn(body.error); return body; }
  await showFrame(state.frame);
  state.lastEdit = body;
  P.showEditStats(body);
  return body;
}
state.setAttr = setAttr;

// Picking: a click (not a drag) on a joint, control, curve or marker selects it.
const ray = new THREE.Raycaster();
let down = null;
renderer.domElement.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
renderer.domElement.addEventListener('pointerup', (e) => {
  if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4 || !drawing) return;
  const rect = renderer.domElement.getBoundingClientRect();
  const p = new THREE.Vector2((e.clientX - rect.left) / rect.width * 2 - 1, -(e.clientY - rect.top) / rect.height * 2 + 1);
  ray.setFromCamera(p, camera);
  ray.params.Line.threshold = drawing.size * 0.3;
  const hit = ray.intersectObjects(drawing.pickables, false)[0];
  // What was hit, for the tests: the node and the kind of object (a curve shape is a Line).
  state.lastPick = hit ? { name: hit.object.userData.name, object: hit.object.type } : null;
  if (hit) select(hit.object.userData.name);
});
const canvasSize = () => [renderer.domElement.clientWidth, renderer.domElement.clientHeight];
state.screenPosition = (name) => drawing?.screenPosition(name, camera, ...canvasSize());
state.curveScreenPosition = (name, k) => drawing?.curveScreenPosition(name, k, camera, ...canvasSize());

// Timeline: play at the rig's fps (frames the server cannot keep up with are skipped).
let playStart = 0, playFrom = 1;
function setPlaying(on) {
  state.playing = on;
  $('play').textContent = on ? '⏸' : '▶';
  playStart = performance.now(); playFrom = state.frame;
}
state.setPlaying = setPlaying;

/// Plays `n` frames as fast as they come (server evaluation, transfer, drawing, one
/// animation frame each): the rate playback can reach, with the time of each part.
state.measurePlayback = async (n) => {
  setPlaying(false);
  const len = state.end - state.start + 1;
  let evalUs = 0, fetchMs = 0, drawMs = 0;
  const t0 = performance.now();
  for (let k = 0; k < n; k++) {
    const f = state.start + ((state.frame - state.start + 1) % len);
    const a = performance.now();
    const fr = await fetchFrame(f);
    const b = performance.now();
    showBuffer(fr, f);
    render();
    await new Promise((r) => requestAnimationFrame(r));
    drawMs += performance.now() - b; fetchMs += b - a; evalUs += fr.evalUs;
  }
  const ms = performance.now() - t0;
  return { frames: n, fps: n * 1000 / ms, evalMs: evalUs / n / 1000, fetchMs: fetchMs / n, drawMs: drawMs / n,
    frameBytes: state.buffer.byteLength };
};

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
  if (!r.ok) { console.warn(p.error); return; }
  P.renderProfile(p, select);
  if (state.selected) await P.renderGraph(state.selected, select);
  state.profile = p;
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
  if (needsRender) render();
}

// Hot reload: the server sends `reload` (with its timings) when a file the rig uses changed.
let reloading = Promise.resolve();
function listen() {
  const es = new EventSource('/api/events');
  es.addEventListener('reload', (e) => {
    const t = JSON.parse(e.data);
    t.receivedAt = epochMs();
    reloading = reloading.then(() => loadScene(t));
  });
}

resize();
await loadScene();
listen();
requestAnimationFrame(tick);
