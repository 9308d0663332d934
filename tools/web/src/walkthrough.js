// The published walkthrough page (`nestwalk publish`): the scene's GLB drawn with three.js, the
// run's camera path played with a time slider, its contacts as markers and buttons that take the
// camera to the blocking event, its expectations and the run's figures. Bundled at build time with
// three.js (pinned in tools/web/package-lock.json) into one classic script, walkthrough.js; the page
// fetches only run.json and scene.glb beside it.
//
// Frames: run.json gives positions in the scene's local frame (metres from the map origin: x east,
// y north, z up); the GLB is in glTF's frame, +y up, a local point (x, y, z) at (x, z, -y)
// (render/gltf_scene_writer.h). Headings are degrees clockwise from north, pitch degrees up.
// For tests: window.nestwalk = {ready, setTime(t), time(), pose(), walker(), selectContact(i),
// showMarkers(on), framesPerSecond(ms)}; pose() and walker() answer in the local frame.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const kTextIntervalMs = 200;

const toGltf = (x, y, z) => new THREE.Vector3(x, z, -y);
const $ = (id) => document.getElementById(id);

function showProblem(text) {
  const box = $('problem');
  box.style.display = 'block';
  box.textContent = text;
}

/// The pose at time t: positions interpolated between the frames around t, headings by the shorter turn.
function poseAt(f, t) {
  const n = f.t.length;
  if (t <= f.t[0]) return { x: f.x[0], y: f.y[0], z: f.z[0], heading: f.heading[0], pitch: f.pitch[0], frame: 0 };
  if (t >= f.t[n - 1]) return { x: f.x[n - 1], y: f.y[n - 1], z: f.z[n - 1], heading: f.heading[n - 1], pitch: f.pitch[n - 1], frame: n - 1 };
  let lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    const mid = (lo + hi) >> 1;
    if (f.t[mid] <= t) lo = mid; else hi = mid;
  }
  const a = (t - f.t[lo]) / (f.t[hi] - f.t[lo]);
  const lerp = (v) => v[lo] + a * (v[hi] - v[lo]);
  let turn = f.heading[hi] - f.heading[lo];
  turn -= 360 * Math.round(turn / 360);
  return { x: lerp(f.x), y: lerp(f.y), z: lerp(f.z), heading: (f.heading[lo] + a * turn + 360) % 360, pitch: lerp(f.pitch), frame: lo };
}

function lookDirection(headingDeg, pitchDeg) {
  const h = THREE.MathUtils.degToRad(headingDeg), p = THREE.MathUtils.degToRad(pitchDeg);
  return toGltf(Math.sin(h) * Math.cos(p), Math.cos(h) * Math.cos(p), Math.sin(p));
}

async function main() {
  let run;
  try {
    run = await (await fetch('run.json')).json();
  } catch (e) {
    const fromFile = location.protocol === 'file:';
    showProblem(fromFile
      ? 'This browser does not let a page opened from a file read the files beside it. Serve the folder: ' +
        'run `python3 -m http.server` in it and open http://localhost:8000/ (or start Chromium with ' +
        '--allow-file-access-from-files).'
      : 'run.json could not be read: ' + e.message);
    throw e;
  }
  const f = run.frames;
  const duration = f.t[f.t.length - 1];
  $('title').textContent = run.title;
  $('summary').textContent = `${run.summary}`;

  const view = $('view');
  const renderer = new THREE.WebGLRenderer({ antialias: false });
  renderer.outputColorSpace = THREE.LinearSRGBColorSpace; // colours as the offscreen renderer draws them
  renderer.setPixelRatio(1);
  view.prepend(renderer.domElement);
  // The offscreen renderer's camera range, sky (its horizon colour) and haze (render/view_depth.h).
  const scene = new THREE.Scene();
  const sky = new THREE.Color(...run.sky_horizon_rgb);
  scene.background = sky;
  scene.fog = new THREE.Fog(sky, run.haze_m[0], run.haze_m[1]);
  const camera = new THREE.PerspectiveCamera(run.fov_y_deg, 16 / 9, run.near_m, run.far_m);
  scene.add(camera);
  // OSG's fixed-function light, roughly: a headlight of diffuse 0.8 and some ambient (three.js's
  // lights are physical: a Lambert surface takes intensity / pi, hence the factors of pi).
  scene.add(new THREE.AmbientLight(0xffffff, 0.3 * Math.PI));
  const headlight = new THREE.DirectionalLight(0xffffff, 0.8 * Math.PI);
  camera.add(headlight);
  headlight.position.set(0, 0, 1);

  const gltf = await new GLTFLoader().loadAsync(run.scene);
  // As OSG's fixed-function pipeline draws them: raw texels, and Lambert shading (per vertex, as
  // Gouraud) for the lit materials, which also costs a software rasterizer far less than PBR.
  gltf.scene.traverse((o) => {
    if (!o.isMesh) return;
    const lambert = (m) => {
      if (m.map) m.map.colorSpace = THREE.NoColorSpace;
      if (!m.isMeshStandardMaterial) return m;
      return new THREE.MeshLambertMaterial({ color: m.color, map: m.map, vertexColors: m.vertexColors,
        transparent: m.transparent, opacity: m.opacity, side: m.side, name: m.name });
    };
    o.material = Array.isArray(o.material) ? o.material.map(lambert) : lambert(o.material);
  });
  scene.add(gltf.scene);

  const walker = new THREE.Mesh(new THREE.SphereGeometry(0.6, 16, 12), new THREE.MeshBasicMaterial({ color: 0xff3b30 }));
  scene.add(walker);
  const markers = new THREE.Group(); // the page's own additions to the scene: contact markers
  for (const c of run.contacts) {
    const marker = new THREE.Mesh(new THREE.ConeGeometry(0.8, 2.0, 12), new THREE.MeshBasicMaterial({ color: 0xffcc00 }));
    marker.position.copy(toGltf(c.x, c.y, c.z + 3.0));
    marker.rotation.x = Math.PI;
    markers.add(marker);
  }
  scene.add(markers);

  const orbit = new OrbitControls(camera, renderer.domElement);
  orbit.enabled = false;
  let t = 0, playing = false, last = performance.now(), selected = null, lastText = 0;
  const slider = $('time');
  slider.max = String(duration);

  function place() {
    const p = poseAt(f, t);
    const eye = toGltf(p.x, p.y, p.z);
    walker.position.copy(eye);
    walker.visible = orbit.enabled;
    if (!orbit.enabled) {
      camera.position.copy(eye);
      camera.lookAt(eye.clone().add(lookDirection(p.heading, p.pitch)));
    }
    // The text at most every kTextIntervalMs while playing: a page relayout per frame costs frames.
    const now = performance.now();
    if (playing && now - lastText < kTextIntervalMs) return p;
    lastText = now;
    slider.value = String(t);
    $('clock').textContent = `${t.toFixed(2)} s / ${duration.toFixed(1)} s`;
    const blocked = f.blocked[p.frame] ? ' (blocked)' : '';
    $('info').textContent = selected !== null
      ? `${run.contacts[selected].unit}: contact at ${run.contacts[selected].time_s.toFixed(2)} s, stopped ` +
        `${(1000 * run.contacts[selected].stop_gap_m).toFixed(0)} mm short`
      : `t = ${t.toFixed(2)} s${blocked}`;
    return p;
  }
  function resize() {
    const w = view.clientWidth, h = view.clientHeight;
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
  }
  window.addEventListener('resize', resize);
  resize();

  function setTime(value) {
    t = Math.min(Math.max(value, 0), duration);
    place();
    renderer.render(scene, camera);
  }
  function selectContact(i) {
    playing = false;
    $('play').textContent = 'Play';
    orbit.enabled = false;
    $('orbit').checked = false;
    selected = i;
    setTime(run.contacts[i].time_s);
  }
  $('play').onclick = () => {
    playing = !playing;
    selected = null;
    if (playing && t >= duration) t = 0;
    $('play').textContent = playing ? 'Pause' : 'Play';
  };
  slider.oninput = () => { selected = null; setTime(parseFloat(slider.value)); };
  $('orbit').onchange = () => {
    orbit.enabled = $('orbit').checked;
    if (orbit.enabled) orbit.target.copy(walker.position);
    place();
  };
  run.contacts.forEach((c, i) => {
    const b = document.createElement('button');
    b.className = 'contact';
    b.textContent = `${c.time_s.toFixed(2)} s  ${c.unit} (${c.kind})`;
    b.onclick = () => selectContact(i);
    $('contacts').appendChild(b);
  });
  if (!run.contacts.length) $('contacts').textContent = 'none';
  for (const e of run.expectations) {
    const d = document.createElement('div');
    d.className = e.met ? 'met' : 'failed';
    d.textContent = `${e.met ? 'met' : 'FAILED'}: ${e.text}`;
    $('expectations').appendChild(d);
  }
  if (!run.expectations.length) $('expectations').textContent = 'none';
  for (const fig of run.figures) {
    const h = document.createElement('h2');
    h.textContent = fig.title;
    const img = document.createElement('img');
    img.src = fig.file;
    img.alt = fig.title;
    $('figures').append(h, img);
  }

  renderer.setAnimationLoop((now) => {
    if (playing) {
      t += (now - last) / 1000;
      if (t >= duration) {
        t = duration;
        playing = false;
        $('play').textContent = 'Play';
      }
    }
    last = now;
    place();
    if (orbit.enabled) orbit.update();
    renderer.render(scene, camera);
  });

  window.nestwalk.setTime = (value) => { selected = null; setTime(value); };
  window.nestwalk.time = () => t;
  window.nestwalk.pose = () => poseAt(f, t);
  window.nestwalk.walker = () => ({ x: walker.position.x, y: -walker.position.z, z: walker.position.y });
  window.nestwalk.selectContact = selectContact;
  window.nestwalk.showMarkers = (on) => { markers.visible = on; renderer.render(scene, camera); };
  window.nestwalk.framesPerSecond = (ms) => new Promise((resolve) => {
    let frames = 0;
    const start = performance.now();
    const count = () => {
      frames += 1;
      if (performance.now() - start < ms) requestAnimationFrame(count);
      else resolve(1000 * frames / (performance.now() - start));
    };
    requestAnimationFrame(count);
  });
  $('info').textContent = 't = 0.00 s';
}

window.nestwalk = {};
window.nestwalk.ready = main();
