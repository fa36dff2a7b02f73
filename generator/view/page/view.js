// The page of `clever-support view`: draws one output folder (model grey, supports orange, on the
// bed) and sends every edit to the server, which writes it into the .scad's [Manual edits] (or a
// Customizer value) and answers with the state read back from the file. The file is the source of
// truth: the page keeps nothing the server did not send.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls.js';
import { STLLoader } from 'three/addons/STLLoader.js';

const COLOURS = { model: 0xb4b8bd, support: 0xf08a24, hover: 0xffd21f, point: 0x2e7df6, blocker: 0x2e7df6,
                  beyond: 0xe01b24, flagged: 0xc013c8 };
const $ = (id) => document.getElementById(id);

async function api(path, body) {
  const r = await fetch(path, body === undefined ? {} :
    { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  const j = await r.json();
  if (!r.ok) throw new Error(j.error || r.statusText);
  return j;
}

// ---- the scene: Z up, the bed at z = 0 ----------------------------------------------------------
const view = $('view');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
view.prepend(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xeef0f3);
const camera = new THREE.PerspectiveCamera(35, 1, 0.1, 5000);
camera.up.set(0, 0, 1);
const controls = new OrbitControls(camera, renderer.domElement);
controls.addEventListener('change', render);
scene.add(new THREE.HemisphereLight(0xffffff, 0x8090a0, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(-1, -2, 3);
scene.add(sun);
const layers = { bed: new THREE.Group(), model: new THREE.Group(), supports: new THREE.Group(), marks: new THREE.Group() };
Object.values(layers).forEach((g) => scene.add(g));

let state = null;          // what the server sent last
let modelMesh = null;      // the placed model
let modelBox = null;       // its bounding box
let strutMeshes = [];      // [{mesh, strutOfFace}] for the kept and the omitted struts
let hovered = -1;          // strut under the pointer
let mode = 'strut';

function render() { renderer.render(scene, camera); }

function resize() {
  const w = view.clientWidth, h = view.clientHeight;
  renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  render();
}
window.addEventListener('resize', resize);

// A bed grid of 10 mm squares (1 mm lines faint) under the model, and an invisible plane at z = 0
// to pick on.
function drawBed(box) {
  layers.bed.clear();
  const size = 10 * Math.ceil((Math.max(box.max.x - box.min.x, box.max.y - box.min.y) * 1.5 + 20) / 10);
  const centre = box.getCenter(new THREE.Vector3());
  const cx = 10 * Math.round(centre.x / 10), cy = 10 * Math.round(centre.y / 10);
  for (const [step, colour] of [[1, 0xdde1e6], [10, 0x9fb3cc]]) {
    const grid = new THREE.GridHelper(size, size / step, colour, colour);
    grid.rotation.x = Math.PI / 2;
    grid.position.set(cx, cy, step === 1 ? -0.01 : 0);
    layers.bed.add(grid);
  }
  const plane = new THREE.Mesh(new THREE.PlaneGeometry(size, size),
    new THREE.MeshBasicMaterial({ visible: false, side: THREE.DoubleSide }));
  plane.position.set(cx, cy, 0);
  plane.name = 'bed';
  layers.bed.add(plane);
}

function setCamera(where) {
  if (!modelBox) return;
  const c = modelBox.getCenter(new THREE.Vector3());
  const r = modelBox.getSize(new THREE.Vector3()).length() * 0.5 + 5;
  const d = r / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2)) * 0.9;
  const dirs = { front: [0.55, -1, 0.7], below: [0.35, -0.6, -1], top: [0.001, -0.001, 1] };
  const v = new THREE.Vector3(...dirs[where]).normalize().multiplyScalar(d);
  camera.position.copy(c).add(v);
  controls.target.copy(c);
  controls.update();
  render();
}

// ---- supports: each strut a square frustum between its end widths, as the N-profile's outline --
function frustum(positions, top, bottom, wt, wb) {
  const a = new THREE.Vector3(...top), b = new THREE.Vector3(...bottom);
  const corners = (p, w) => [[-1, -1], [1, -1], [1, 1], [-1, 1]].map(([sx, sy]) =>
    new THREE.Vector3(p.x + sx * w / 2, p.y + sy * w / 2, p.z));
  const T = corners(a, wt), B = corners(b, wb);
  const tri = (p, q, r) => positions.push(p.x, p.y, p.z, q.x, q.y, q.z, r.x, r.y, r.z);
  for (let i = 0; i < 4; ++i) {
    const j = (i + 1) % 4;
    tri(B[i], B[j], T[j]);
    tri(B[i], T[j], T[i]);
  }
  tri(T[0], T[1], T[2]); tri(T[0], T[2], T[3]);
  tri(B[0], B[2], B[1]); tri(B[0], B[3], B[2]);
  return 12;  // triangles
}

function meshOf(positions, material) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
  g.computeVertexNormals();
  const colours = new Float32Array(positions.length);
  g.setAttribute('color', new THREE.BufferAttribute(colours, 3));
  const mesh = new THREE.Mesh(g, material);
  paint(mesh, 0, positions.length / 9, material.userData.base);
  return mesh;
}

function paint(mesh, firstTri, count, hex) {
  const c = new THREE.Color(hex), col = mesh.geometry.attributes.color;
  for (let v = firstTri * 3; v < (firstTri + count) * 3; ++v) col.setXYZ(v, c.r, c.g, c.b);
  col.needsUpdate = true;
}

function drawSupports() {
  layers.supports.clear();
  strutMeshes = [];
  if (!state || !state.struts) return;
  const solid = new THREE.MeshStandardMaterial({ vertexColors: true, roughness: 0.7 });
  solid.userData.base = COLOURS.support;
  const ghost = new THREE.MeshStandardMaterial({ vertexColors: true, transparent: true, opacity: 0.35, depthWrite: false });
  ghost.userData.base = COLOURS.support;
  for (const omitted of [false, true]) {
    const positions = [], strutOfFace = [];
    state.struts.forEach((s, i) => {
      if (s[6] !== omitted) return;
      const n = frustum(positions, s[0], s[1], s[2], s[3]);
      for (let k = 0; k < n; ++k) strutOfFace.push(i);
    });
    if (!positions.length) continue;
    const mesh = meshOf(positions, omitted ? ghost : solid);
    mesh.name = omitted ? 'omitted' : 'struts';
    layers.supports.add(mesh);
    strutMeshes.push({ mesh, strutOfFace });
  }
  const tipPositions = [];
  for (const t of state.tips) frustum(tipPositions, t[0], t[1], t[2], t[3]);
  if (tipPositions.length) {
    const tips = meshOf(tipPositions, solid);
    tips.name = 'tips';
    layers.supports.add(tips);
  }
  hovered = -1;
}

function sphere(at, radius, colour) {
  const m = new THREE.Mesh(new THREE.SphereGeometry(radius, 16, 12), new THREE.MeshStandardMaterial({ color: colour }));
  m.position.set(...at);
  return m;
}

// Support points, blockers (see-through, as in the OpenSCAD preview) and check's flags.
function drawMarks() {
  layers.marks.clear();
  if (!state) return;
  const r = Math.max(0.35, (state.sampling || 2) * 0.2);
  if (state.edits) {
    state.edits.support_points.forEach((p) => layers.marks.add(sphere(p, r, COLOURS.point)));
    for (const [lo, hi] of state.edits.support_blockers) layers.marks.add(blockerBox(lo, hi));
  }
  const check = state.check || {};
  (check.uncovered || []).forEach((p) => layers.marks.add(sphere(p, r, COLOURS.beyond)));
  (check.flagged || []).forEach((f) => layers.marks.add(sphere(f.at, r * 1.3, COLOURS.flagged)));
}

function blockerBox(lo, hi) {
  const size = [0, 1, 2].map((i) => Math.max(0.01, hi[i] - lo[i]));
  const g = new THREE.BoxGeometry(...size);
  const box = new THREE.Mesh(g, new THREE.MeshBasicMaterial({ color: COLOURS.blocker, transparent: true, opacity: 0.2, depthWrite: false }));
  box.add(new THREE.LineSegments(new THREE.EdgesGeometry(g), new THREE.LineBasicMaterial({ color: COLOURS.blocker })));
  box.position.set((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
  return box;
}

// ---- the side panel -------------------------------------------------------------------------------
const fmt = (x, d = 1) => (x === undefined || x === null ? '–' : Number(x).toFixed(d));

function showPanel() {
  $('title').textContent = state.name;
  $('file').textContent = state.scad;
  const rep = state.report;
  const rows = [];
  if (rep) {
    const s = rep.supports, c = rep.columns_baseline, save = rep.saving_vs_columns || {};
    rows.push(['support volume', fmt(s.support_volume_mm3) + ' mm³'], ['struts', s.struts], ['tips', s.tips],
      ['bed contacts', s.bed_contacts], ['model contacts', s.model_contacts], ['strut length', fmt(s.total_strut_length_mm) + ' mm']);
    if (c) rows.push(['columns baseline', fmt(c.support_volume_mm3) + ' mm³'],
      ['saving vs columns', fmt(100 * save.volume, 0) + ' % of volume']);
  } else rows.push(['report', 'none (regrow writes it)']);
  $('figures').replaceChildren(...rows.map(([k, v]) => {
    const tr = document.createElement('tr');
    tr.innerHTML = '<td></td><td></td>';
    tr.children[0].textContent = k;
    tr.children[1].textContent = v;
    return tr;
  }));
  const check = state.check || {};
  const verdict = $('verdict');
  if (check.error) { verdict.className = 'fail'; verdict.textContent = check.error; }
  else if (check.summary !== undefined) {
    verdict.className = check.ok ? 'ok' : 'fail';
    const leftOut = check.left_out_area_mm2 > 0 ? ` (${fmt(check.left_out_area_mm2)} mm² left out on purpose by your edits)` : '';
    verdict.textContent = check.ok ? `passes: every overhang within reach, every solid sound${leftOut}`
      : (check.coverage_ok ? '' : `${fmt(check.uncovered_area_mm2)} mm² of overhang beyond reach (red). `) +
        (check.flagged.length ? `${check.flagged.length} solid problem(s) (magenta).` : '');
    $('checksummary').textContent = check.summary;
  }
  showSliders();
  showEdits();
}

function showSliders() {
  const box = $('sliders');
  box.replaceChildren();
  for (const s of state.sliders || []) {
    const div = document.createElement('div');
    div.className = 'slider';
    div.innerHTML = '<label><span></span><output></output></label><input type="range">';
    div.querySelector('span').textContent = s.name;
    div.title = s.about;
    const out = div.querySelector('output'), input = div.querySelector('input');
    Object.assign(input, { min: s.min, max: s.max, step: s.step, value: s.value, name: s.name });
    out.textContent = s.value;
    input.addEventListener('input', () => { out.textContent = input.value; });
    input.addEventListener('change', () => edit({ op: 'set', name: s.name, value: Number(input.value) }));
    box.append(div);
  }
}

function showEdits() {
  const e = state.edits;
  const box = $('edits');
  box.replaceChildren();
  if (!e) return;
  const list = (title, items, label, remove) => {
    const h = document.createElement('div');
    h.textContent = `${title}: ${items.length ? '' : 'none'}`;
    box.append(h);
    if (!items.length) return;
    const ul = document.createElement('ul');
    items.forEach((item, i) => {
      const li = document.createElement('li');
      li.textContent = label(item) + ' ';
      const b = document.createElement('button');
      b.textContent = '✕';
      b.title = 'remove';
      b.addEventListener('click', () => edit(remove(item, i)));
      li.append(b);
      ul.append(li);
    });
    box.append(ul);
  };
  const p3 = (p) => `[${p.map((x) => fmt(x, 2)).join(', ')}]`;
  list('omit_struts', e.omit_struts, (s) => `strut ${s}`, (s) => ({ op: 'toggle_strut', strut: s }));
  list('support_points', e.support_points, p3, (_, i) => ({ op: 'remove_point', index: i }));
  list('support_blockers', e.support_blockers, ([lo, hi]) => `${p3(lo)} – ${p3(hi)}`, (_, i) => ({ op: 'remove_blocker', index: i }));
}

function message(text, kind = 'error') {
  const m = $('message');
  m.hidden = !text;
  m.className = kind;
  m.textContent = text || '';
}

// ---- loading and editing -----------------------------------------------------------------------------
async function loadModel() {
  const buf = await (await fetch('files/model.stl')).arrayBuffer();
  const g = new STLLoader().parse(buf);
  layers.model.clear();
  modelMesh = new THREE.Mesh(g, new THREE.MeshStandardMaterial({ color: COLOURS.model, roughness: 0.8, side: THREE.DoubleSide }));
  modelMesh.name = 'model';
  layers.model.add(modelMesh);
  g.computeBoundingBox();
  modelBox = g.boundingBox.clone();
  drawBed(modelBox);
}

function take(newState) {
  state = newState;
  if (state.error) message(state.error);
  drawSupports();
  drawMarks();
  showPanel();
  render();
}

async function edit(op) {
  try {
    take(await api('api/edit', op));
    message('');
  } catch (e) {
    message(e.message);
    showSliders();  // back to the file's values
  }
}

// ---- pointing: hover shows, a click (not a drag) edits -------------------------------------------------
const raycaster = new THREE.Raycaster();
function pick(clientX, clientY, objects) {
  const r = renderer.domElement.getBoundingClientRect();
  const ndc = new THREE.Vector2(((clientX - r.left) / r.width) * 2 - 1, -((clientY - r.top) / r.height) * 2 + 1);
  raycaster.setFromCamera(ndc, camera);
  return raycaster.intersectObjects(objects, false)[0] || null;
}
const pickables = () => [modelMesh, ...strutMeshes.map((s) => s.mesh), layers.bed.getObjectByName('bed')].filter(Boolean);

function strutOf(hit) {
  const s = hit && strutMeshes.find((x) => x.mesh === hit.object);
  return s ? s.strutOfFace[hit.faceIndex] : -1;
}

function setHover(i) {
  if (i === hovered) return;
  for (const k of [hovered, i]) {
    if (k < 0) continue;
    for (const { mesh, strutOfFace } of strutMeshes) {
      const first = strutOfFace.indexOf(k);
      if (first >= 0) paint(mesh, first, 12, k === i ? COLOURS.hover : COLOURS.support);
    }
  }
  hovered = i;
  render();
}

function describe(hit) {
  const i = strutOf(hit);
  if (i >= 0) {
    const s = state.struts[i];
    return `strut ${i} · ${s[4]} · width ${fmt(s[2], 2)}–${fmt(s[3], 2)} mm · length ${fmt(s[5])} mm` +
      (s[6] ? ' · omitted (click to keep)' : '');
  }
  if (hit && hit.object === modelMesh) {
    const p = hit.point;
    return `x ${fmt(p.x, 2)}  y ${fmt(p.y, 2)}  z ${fmt(p.z, 2)} mm`;
  }
  return '';
}

// A face that looks down and is above the bed (the faces standing on the bed need no support).
const isUnderside = (hit) => hit && hit.object === modelMesh && hit.face && hit.point.z > 0.3 &&
  hit.face.normal.clone().transformDirection(modelMesh.matrixWorld).z < -0.05;

let down = null, dragBox = null;
const canvas = renderer.domElement;
canvas.addEventListener('pointermove', (ev) => {
  if (down && mode === 'blocker' && down.hit) return dragBlocker(ev);
  // Adding points: the model point the click would take, through the struts.
  const hit = pick(ev.clientX, ev.clientY, mode === 'point' ? [modelMesh] : pickables());
  setHover(strutOf(hit));
  const text = describe(hit);
  const tip = $('tip');
  tip.hidden = !text;
  tip.textContent = text;
  const r = view.getBoundingClientRect();
  const left = ev.clientX - r.left + 14;
  tip.style.left = `${Math.min(left, r.width - tip.offsetWidth - 4)}px`;
  tip.style.top = `${ev.clientY - r.top + 14}px`;
});
// Captured before OrbitControls sees it, so that a blocker's drag does not orbit.
canvas.addEventListener('pointerdown', (ev) => {
  if (ev.button !== 0) return;
  down = { x: ev.clientX, y: ev.clientY, hit: null };
  if (mode === 'blocker') {
    const hit = pickModelOrBed(ev.clientX, ev.clientY);
    if (hit) { down.hit = hit; controls.enabled = false; }
  }
}, { capture: true });
canvas.addEventListener('pointerup', (ev) => {
  if (!down) return;
  const moved = Math.hypot(ev.clientX - down.x, ev.clientY - down.y) > 4;
  const start = down;
  down = null;
  controls.enabled = true;
  if (mode === 'blocker' && start.hit) return finishBlocker(start.hit, ev);
  if (moved) return;  // an orbit
  const hit = pick(ev.clientX, ev.clientY, pickables());
  if (mode === 'strut') {
    const i = strutOf(hit);
    if (i >= 0) edit({ op: 'toggle_strut', strut: i });
  } else if (mode === 'point') {
    // Through the supports: a point goes on the model wherever it is seen.
    const onModel = pick(ev.clientX, ev.clientY, [modelMesh]);
    if (isUnderside(onModel)) edit({ op: 'add_point', at: onModel.point.toArray() });
    else message('Click the model\'s underside (a face that looks down); "Below" turns the view to it.', 'info');
  }
});

// The model where it is seen, even from under the bed; else the bed.
const pickModelOrBed = (x, y) => pick(x, y, [modelMesh]) || pick(x, y, [layers.bed.getObjectByName('bed')]);

// A blocker: the box over the dragged rectangle, from below the bed to just above the highest
// point dragged over (drag across an underside to leave it unsupported).
function blockerCorners(a, b) {
  const top = Math.max(a.z, b.z) + 0.5;
  return [[Math.min(a.x, b.x), Math.min(a.y, b.y), -1], [Math.max(a.x, b.x), Math.max(a.y, b.y), Math.max(top, 0.5)]];
}
function dragEnd(ev, startHit) {
  const hit = pickModelOrBed(ev.clientX, ev.clientY);
  if (hit) return hit.point;
  // Off the model and the bed: on the horizontal plane of the start.
  const plane = new THREE.Plane(new THREE.Vector3(0, 0, 1), -startHit.point.z);
  return raycaster.ray.intersectPlane(plane, new THREE.Vector3()) || startHit.point;
}
function dragBlocker(ev) {
  const [lo, hi] = blockerCorners(down.hit.point, dragEnd(ev, down.hit));
  if (dragBox) layers.marks.remove(dragBox);
  dragBox = blockerBox(lo, hi);
  layers.marks.add(dragBox);
  render();
}
function finishBlocker(startHit, ev) {
  if (dragBox) { layers.marks.remove(dragBox); dragBox = null; }
  const [lo, hi] = blockerCorners(startHit.point, dragEnd(ev, startHit));
  if (hi[0] - lo[0] < 0.5 || hi[1] - lo[1] < 0.5) { render(); return message('Drag out a box: press, move, release.', 'info'); }
  edit({ op: 'add_blocker', box: [lo, hi] });
}

function setMode(m) {
  mode = m;
  document.querySelectorAll('[data-mode]').forEach((b) => b.classList.toggle('on', b.dataset.mode === m));
}
document.querySelectorAll('[data-mode]').forEach((b) => b.addEventListener('click', () => setMode(b.dataset.mode)));
document.querySelectorAll('[data-camera]').forEach((b) => b.addEventListener('click', () => setCamera(b.dataset.camera)));
window.addEventListener('keydown', (ev) => {
  const m = { s: 'strut', p: 'point', b: 'blocker' }[ev.key];
  if (m && ev.target === document.body) setMode(m);
});

// ---- regrow: `clever-support regrow` on the server, its progress here -------------------------------
$('regrow').addEventListener('click', async () => {
  $('regrow').disabled = true;
  message('');
  try {
    let st = await api('api/regrow', {});
    $('progress').hidden = false;
    while (st.running) {
      const last = st.lines.filter((l) => /\[\s*\d+%\]/.test(l)).pop();
      if (last) {
        $('bar').style.width = `${/\[\s*(\d+)%\]/.exec(last)[1]}%`;
        $('stage').textContent = last.replace(/^\s*\[\s*\d+%\]\s*/, '');
      }
      await new Promise((r) => setTimeout(r, 250));
      st = await api('api/regrow');
    }
    $('bar').style.width = '100%';
    if (st.exit !== 0) {
      const errors = st.lines.filter((l) => /error|warning/.test(l));
      message((errors.length ? errors : st.lines.slice(-5)).join('\n'));
      $('stage').textContent = `regrow failed (exit ${st.exit})`;
    } else {
      await reload();
      $('stage').textContent = 'regrown';
      window.csView.regrows += 1;
    }
  } catch (e) {
    message(e.message);
  }
  if (!/regrown/.test($('stage').textContent)) window.csView.regrows += 1;  // finished, failed
  $('regrow').disabled = false;
});

async function reload() {
  await loadModel();
  take(await api('api/state'));
}

// ---- for tests and scripts: where things are on the screen ---------------------------------------------
function screenOf(p) {
  const v = new THREE.Vector3(...p).project(camera);
  const r = canvas.getBoundingClientRect();
  return { x: r.left + (v.x + 1) / 2 * r.width, y: r.top + (1 - v.y) / 2 * r.height };
}
window.csView = {
  ready: false,
  regrows: 0,
  state: () => state,
  setCamera,
  // A pixel where strut i is the first thing the pointer meets, or null.
  strutPixel(i) {
    const s = state.struts[i];
    const mid = s[0].map((x, k) => (x + s[1][k]) / 2);
    const at = screenOf(mid);
    return strutOf(pick(at.x, at.y, pickables())) === i ? at : null;
  },
  // A pixel of the model's underside (seen from the current camera), the nearest to `near`
  // (default: the centre), or null.
  undersidePixel(near) {
    const r = canvas.getBoundingClientRect();
    const to = near || { x: (r.left + r.right) / 2, y: (r.top + r.bottom) / 2 };
    let best = null;
    for (let y = r.top + 10; y < r.bottom - 10; y += 12)
      for (let x = r.left + 10; x < r.right - 10; x += 12) {
        if (!isUnderside(pick(x, y, [modelMesh]))) continue;
        const d = Math.hypot(x - to.x, y - to.y);
        if (!best || d < best.d) best = { x, y, d };
      }
    return best;
  },
  // What drawMarks drew, by colour.
  markCount() {
    const count = (hex) => layers.marks.children.filter((m) => m.material && m.material.color &&
      m.material.color.getHex() === hex && m.geometry.type === 'SphereGeometry').length;
    return { beyond: count(COLOURS.beyond), flagged: count(COLOURS.flagged), points: count(COLOURS.point) };
  },
  // How many pixels of the picture are model grey and support orange.
  colourCounts() {
    render();
    const c = document.createElement('canvas');
    c.width = canvas.width; c.height = canvas.height;
    const g = c.getContext('2d');
    g.drawImage(canvas, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    let grey = 0, orange = 0;
    for (let i = 0; i < d.length; i += 4) {
      const [r0, g0, b0] = [d[i], d[i + 1], d[i + 2]];
      if (r0 > 150 && g0 > 60 && g0 < 170 && b0 < 90 && r0 - b0 > 100) ++orange;
      else if (Math.abs(r0 - g0) < 14 && Math.abs(g0 - b0) < 18 && r0 > 40 && r0 < 215) ++grey;
    }
    return { grey, orange, total: d.length / 4 };
  },
};

(async () => {
  resize();
  try {
    await loadModel();
    take(await api('api/state'));
    setCamera('front');
  } catch (e) {
    message(e.message);
  }
  window.csView.ready = true;
})();
