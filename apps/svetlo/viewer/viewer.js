// The viewer (docs/viewer.md): its controls, the view and its state in the query string, the
// same script in svetlo serve's page and the web page (docs/web.md). Every request goes
// through svetloViewer.fetch (backend.js): fetch itself in svetlo serve, svetlo's WebAssembly
// module in a worker in the web page. Both answer them with the job layer's ViewerApi, so that
// a link, a render and an error read the same in both.
"use strict";
const $ = (id) => document.getElementById(id);
const backend = self.svetloViewer;
const W = 480, H = 270;
const client = Math.random().toString(36).slice(2);
let camera = null;       // {position, look_at} of the scene, orbited by the mouse
let pending = false;     // a render is on its way: changes meanwhile are coalesced
let dirty = false;       // the state changed since the render on its way was asked for
let moving = false;      // the view is being dragged or a slider moved: JPEG, then PNG when still
let still = null;        // the timer of the lossless render once the view stops
let sceneJson = null;    // the scene as the server read it (/api/scene)
const overrides = new Map();  // the sliders' keys and values (JSON), as --set writes them
let stream = null;       // the AbortController of the progressive render being shown
window.svetloBusy = () => pending || dirty || moving || stream !== null;  // for tests: a render is due

function state() {
  const sets = $("sets").value.split("\n").map((s) => s.trim()).filter((s) => s.includes("="));
  for (const [key, value] of overrides) sets.push(key + "=" + value);
  if ($("shading").value) sets.push("render.shading=\"" + $("shading").value + "\"");
  if ($("shadows").value) sets.push("render.shadows=\"" + $("shadows").value + "\"");
  if (camera) sets.push("camera.position=" + JSON.stringify(camera.position.map((v) => +v.toFixed(4))));
  const bsets = [];
  if ($("bshading").value) bsets.push("render.shading=\"" + $("bshading").value + "\"");
  if ($("bshadows").value) bsets.push("render.shadows=\"" + $("bshadows").value + "\"");
  return { scene: $("scene").value, engine: $("engine").value, spp: 1 << +$("spp").value, sets,
           aov: $("aov").value, ab: $("abview").value, bengine: $("bengine").value, bsets };
}

function query(s) {
  const q = new URLSearchParams();
  q.set("scene", s.scene);
  q.set("engine", s.engine);
  q.set("spp", s.spp);
  for (const v of s.sets) q.append("set", v);
  if (s.aov) q.set("aov", s.aov);
  if (s.ab) q.set("ab", s.ab);
  if (s.bengine) q.set("b_engine", s.bengine);
  for (const v of s.bsets) q.append("b_set", v);
  return q;
}

function writeQueryString(s) {
  history.replaceState(null, "", "?" + query(s).toString());
  const sets = s.sets.map((v) => " --set '" + v + "'").join("");
  $("command").textContent = "svetlo render " + s.scene + " --engine " + s.engine +
      " --spp " + s.spp + " -W " + W + " -H " + H + sets + " -o out.png" +
      (s.aov ? " --aov " + s.aov + "=" + s.aov + ".png" : "");
}

// While the view moves, fast JPEGs; 300 ms after the last change, one lossless PNG.
function move() {
  moving = true;
  clearTimeout(still);
  still = setTimeout(() => { moving = false; render(); }, 300);
  render();
}

async function render() {
  if (pending) { dirty = true; return; }
  pending = true;
  dirty = false;
  const s = state();
  writeQueryString(s);
  const q = query(s);
  q.set("width", W);
  q.set("height", H);
  q.set("client", client);
  if (moving) { q.set("format", "jpeg"); q.set("preview", "1"); }  // docs/viewer.md
  const t0 = performance.now();
  $("view-b").classList.toggle("hidden", s.ab !== "split");
  $("divider").classList.toggle("hidden", s.ab !== "split");
  if (stream) stream.abort();  // any change ends the progressive render on the screen
  if (s.ab) {
    await compareAB(s, q, t0);
    pending = false;
    if (dirty) render();
    return;
  }
  if (engines[s.engine] && engines[s.engine].shows_passes && !s.aov) {
    progressive(s, q, t0);
    return;
  }
  try {
    const r = await backend.fetch("/api/render?" + q.toString());
    if (r.ok) {
      const blob = await r.blob();
      const old = $("view").src;
      $("view").src = URL.createObjectURL(blob);
      if (old.startsWith("blob:")) URL.revokeObjectURL(old);
      $("error").textContent = "";
      $("status").textContent = r.headers.get("X-Svetlo-Technique") + ", " + r.headers.get("X-Svetlo-Spp") + " spp, render " +
          (+r.headers.get("X-Svetlo-Seconds")).toFixed(3) + " s, encode " +
          (+r.headers.get("X-Svetlo-Encode-Seconds")).toFixed(3) + " s (" + blob.type.slice(6) +
          ", " + (blob.size / 1024).toFixed(0) + " KiB), shown after " +
          (performance.now() - t0).toFixed(0) + " ms";
    } else if (r.status !== 409) {  // 409: superseded by a newer request of this page
      $("error").textContent = await r.text();
    }
  } catch (e) {
    $("error").textContent = String(e);
  }
  pending = false;
  if (dirty) render();
}

// Path and radiosity refine pass by pass (/api/progressive): each frame shows as it comes,
// with the samples reached and the time; the first frame ends `pending`, so that changes
// made meanwhile start the next render (which ends this one) as soon as it is on the screen.
function showImage(blob) {
  const old = $("view").src;
  $("view").src = URL.createObjectURL(blob);
  if (old.startsWith("blob:")) URL.revokeObjectURL(old);
}
async function progressive(s, q, t0) {
  q.delete("format");
  const control = new AbortController();
  stream = control;
  let first = true;
  const firstFrame = () => {
    if (!first) return;
    first = false;
    pending = false;
    if (dirty) render();
  };
  try {
    const r = await backend.fetch("/api/progressive?" + q.toString(), { signal: control.signal });
    if (!r.ok) {
      if (r.status !== 409) $("error").textContent = await r.text();
    } else {
      const reader = r.body.getReader();
      let buf = new Uint8Array(0);
      const u32 = (at) => ((buf[at] << 24) | (buf[at + 1] << 16) | (buf[at + 2] << 8) | buf[at + 3]) >>> 0;
      for (;;) {
        const { done, value } = await reader.read();
        if (done) break;
        const joined = new Uint8Array(buf.length + value.length);
        joined.set(buf);
        joined.set(value, buf.length);
        buf = joined;
        while (buf.length >= 4) {
          const h = u32(0);
          if (buf.length < 8 + h) break;
          const header = JSON.parse(new TextDecoder().decode(buf.subarray(4, 4 + h)));
          if (header.error) { $("error").textContent = header.error; buf = new Uint8Array(0); break; }
          const n = u32(4 + h);
          if (buf.length < 8 + h + n) break;
          showImage(new Blob([buf.slice(8 + h, 8 + h + n)], { type: header.type }));
          buf = buf.slice(8 + h + n);
          $("error").textContent = "";
          $("status").textContent = header.technique + ", " + header.spp + " spp, " +
              header.seconds.toFixed(2) + " s" + (header.final ? ", done" : ", refining") +
              ", first shown after " + (performance.now() - t0).toFixed(0) + " ms";
          firstFrame();
        }
      }
    }
  } catch (e) {
    if (e.name !== "AbortError") $("error").textContent = String(e);
  }
  if (stream === control) stream = null;
  firstFrame();
}

// A and B rendered by the server side by side (/api/diff): split with a divider, or ꟻLIP's
// error of B against A in false colour, with the numbers of svetlo diff.
let split = 0.5;
async function compareAB(s, q, t0) {
  q.delete("format");
  q.delete("aov");
  try {
    const r = await backend.fetch("/api/diff?" + q.toString());
    if (!r.ok) { $("error").textContent = await r.text(); return; }
    const d = await r.json();
    $("view").src = s.ab === "diff" ? d.error : d.a;
    $("view-b").src = d.b;
    placeDivider();
    $("error").textContent = "";
    $("status").textContent = "B against A: mae " + d.mae.toPrecision(4) + ", rmse " +
        d.rmse.toPrecision(4) + ", relmse " + d.relmse.toPrecision(4) + ", ꟻLIP " +
        d.flip.toFixed(4) + "; renders " + d.seconds.map((t) => t.toFixed(3) + " s").join(" and ") +
        ", shown after " + (performance.now() - t0).toFixed(0) + " ms";
  } catch (e) {
    $("error").textContent = String(e);
  }
}
function placeDivider() {
  $("view-b").style.clipPath = "inset(0 0 0 " + (100 * split).toFixed(2) + "%)";
  $("divider").style.left = (100 * split).toFixed(2) + "%";
}
let dividing = false;
$("divider").addEventListener("pointerdown", (e) => { dividing = true; e.stopPropagation(); });
window.addEventListener("pointermove", (e) => {
  if (!dividing) return;
  const rect = $("view").getBoundingClientRect();
  split = Math.max(0, Math.min(1, (e.clientX - rect.left) / rect.width));
  placeDivider();
});
window.addEventListener("pointerup", () => { dividing = false; });

async function loadScene(keepCamera) {
  const r = await backend.fetch("/api/scene?scene=" + encodeURIComponent($("scene").value));
  if (!r.ok) { $("error").textContent = await r.text(); return; }
  const scene = await r.json();
  sceneJson = scene;
  buildSliders();
  const c = scene.camera || {};
  if (!keepCamera || !camera)
    camera = { position: c.position || [0, 0, 5], look_at: c.look_at || [0, 0, 0] };
}

// Orbit: drag to turn about look_at, wheel to zoom.
function orbit(dx, dy, zoom) {
  if (!camera) return;
  const p = camera.position, t = camera.look_at;
  const v = [p[0] - t[0], p[1] - t[1], p[2] - t[2]];
  let r = Math.hypot(v[0], v[1], v[2]) * zoom;
  let theta = Math.atan2(v[0], v[2]) - dx * 0.01;
  let phi = Math.acos(Math.max(-1, Math.min(1, v[1] / Math.hypot(v[0], v[1], v[2])))) - dy * 0.01;
  phi = Math.max(0.05, Math.min(Math.PI - 0.05, phi));
  camera.position = [t[0] + r * Math.sin(phi) * Math.sin(theta), t[1] + r * Math.cos(phi),
                     t[2] + r * Math.sin(phi) * Math.cos(theta)];
  move();
}
// One pointer (mouse, pen or finger) orbits; two fingers pinch to zoom.
let drag = null;
const touches = new Map();  // pointerId -> [x, y]
const spread = () => { const [a, b] = [...touches.values()]; return Math.hypot(a[0] - b[0], a[1] - b[1]); };
$("view").addEventListener("pointerdown", (e) => {
  touches.set(e.pointerId, [e.clientX, e.clientY]);
  drag = touches.size === 1 ? [e.clientX, e.clientY, e.clientX, e.clientY] : null;
});
window.addEventListener("pointerup", async (e) => {
  if (drag && Math.hypot(e.clientX - drag[2], e.clientY - drag[3]) < 3) inspect(e);
  touches.delete(e.pointerId);
  drag = null;
});
window.addEventListener("pointercancel", (e) => { touches.delete(e.pointerId); drag = null; });
window.addEventListener("pointermove", (e) => {
  if (touches.size === 2 && touches.has(e.pointerId)) {
    const before = spread();
    touches.set(e.pointerId, [e.clientX, e.clientY]);
    if (before > 0 && spread() > 0) orbit(0, 0, before / spread());
    return;
  }
  if (!drag) return;
  orbit(e.clientX - drag[0], e.clientY - drag[1], 1);
  drag[0] = e.clientX; drag[1] = e.clientY;
});
$("view").addEventListener("wheel", (e) => { e.preventDefault(); orbit(0, 0, e.deltaY > 0 ? 1.1 : 1 / 1.1); });

// Pixel inspection: the trace of svetlo trace at the clicked pixel.
async function inspect(e) {
  const rect = $("view").getBoundingClientRect();
  const x = Math.floor((e.clientX - rect.left) * W / rect.width);
  const y = Math.floor((e.clientY - rect.top) * H / rect.height);
  const q = query(state());
  q.delete("aov");
  q.set("width", W); q.set("height", H); q.set("x", x); q.set("y", y);
  const r = await backend.fetch("/api/trace?" + q.toString());
  if (!r.ok) { $("error").textContent = await r.text(); return; }
  const t = await r.json();
  $("pixel").textContent = "pixel (" + x + ", " + y + "): " + t.total.map((v) => v.toPrecision(4)).join(" ") +
      "\n" + t.rays.map((ray) => ray.kind + (ray.note ? " (" + ray.note + ")" : "")).join("\n");
}

// Sliders: the scene's first light, the shadow map, the path depth, and the chosen
// material's values. Each writes its key into `overrides` once moved (so into the query
// string and the command line); restoring a view moves them back.
const colourKeys = ["albedo", "kd", "base_color"];
const numberKeys = { shininess: [1, 1000, true], roughness: [0, 1, false], metallic: [0, 1, false] };
const jsonNumber = (v) => +(+v).toPrecision(4);

function slider(parent, key, label, min, max, step, fromValue, toValue, initial) {
  const l = document.createElement("label");
  const span = document.createElement("span");
  const input = document.createElement("input");
  Object.assign(input, { type: "range", min, max, step });
  input.dataset.key = key;
  const shown = overrides.has(key) ? fromValue(JSON.parse(overrides.get(key))) : fromValue(initial);
  input.value = shown;
  const show = () => { span.textContent = " " + JSON.stringify(toValue(+input.value)); };
  // Until moved, the scene's own value (the slider's steps may not hold it exactly).
  span.textContent = " " + JSON.stringify(overrides.has(key) ? JSON.parse(overrides.get(key)) : initial);
  input.addEventListener("input", () => {
    overrides.set(key, JSON.stringify(toValue(+input.value)));
    show();
    move();
  });
  l.append(label, span, input);
  parent.appendChild(l);
}

function colour(parent, key, label, initial) {
  const l = document.createElement("label");
  const input = document.createElement("input");
  input.type = "color";
  input.dataset.key = key;
  const c = overrides.has(key) ? JSON.parse(overrides.get(key)) : initial;
  const rgb = Array.isArray(c) ? c : [c, c, c];
  const hex = (v) => Math.round(Math.pow(Math.max(0, Math.min(1, +v)), 1 / 2.2) * 255).toString(16).padStart(2, "0");
  input.value = "#" + rgb.map(hex).join("");
  input.addEventListener("input", () => {
    const v = [1, 3, 5].map((i) => jsonNumber(Math.pow(parseInt(input.value.substr(i, 2), 16) / 255, 2.2)));
    overrides.set(key, JSON.stringify(v));
    render();
  });
  l.append(label + " ", input);
  parent.appendChild(l);
}

function buildMaterialSliders() {
  const box = $("material-sliders");
  box.textContent = "";
  const name = $("material").value;
  const m = (sceneJson.materials || {})[name];
  if (!m) return;
  for (const k of colourKeys)
    if (k in m || (m.type === "lambert" && k === "albedo") || (m.type === "phong" && k === "kd") ||
        (m.type === "cook_torrance" && k === "base_color"))
      colour(box, "materials." + name + "." + k, k, k in m ? m[k] : 0.8);
  for (const [k, [lo, hi, log]] of Object.entries(numberKeys)) {
    const applies = k in m || (k === "shininess" && m.type === "phong") ||
        (k !== "shininess" && m.type === "cook_torrance");
    if (!applies || typeof (m[k] ?? 0) !== "number") continue;
    const initial = k in m ? m[k] : { shininess: 32, roughness: 0.5, metallic: 0 }[k];
    if (log) slider(box, "materials." + name + "." + k, k, 0, 100, 1,
                    (v) => 100 * Math.log(v / lo) / Math.log(hi / lo),
                    (x) => jsonNumber(lo * Math.pow(hi / lo, x / 100)), initial);
    else slider(box, "materials." + name + "." + k, k, 0, 100, 1, (v) => 100 * v,
                (x) => jsonNumber(x / 100), initial);
  }
}

function buildSliders() {
  const names = Object.keys(sceneJson.materials || {});
  $("material").textContent = "";
  for (const n of names) {
    const o = document.createElement("option");
    o.textContent = n;
    $("material").appendChild(o);
  }
  buildMaterialSliders();
  const box = $("scene-sliders");
  box.textContent = "";
  const light = (sceneJson.lights || [])[0];
  const c = sceneJson.camera || {};
  const p = c.position || [0, 0, 5], t = c.look_at || [0, 0, 0];
  const reach = Math.max(1, Math.hypot(p[0] - t[0], p[1] - t[1], p[2] - t[2]));
  if (light && Array.isArray(light.position)) {
    ["x", "y", "z"].forEach((axis, a) => {
      const key = "lights.0.position";
      const at = () => overrides.has(key) ? JSON.parse(overrides.get(key)) : light.position.slice();
      slider(box, key, "light " + axis, -100, 100, 1,
             (v) => 100 * (v[a] - light.position[a]) / reach,
             (x) => { const q = at(); q[a] = jsonNumber(light.position[a] + x * reach / 100); return q; },
             light.position);
    });
  }
  for (const k of ["intensity", "irradiance", "radiance"]) {
    if (!light || !(k in light)) continue;
    const base = light[k];
    const scale = (f) => Array.isArray(base) ? base.map((v) => jsonNumber(v * f)) : jsonNumber(base * f);
    const first = Array.isArray(base) ? base[0] : base;
    slider(box, "lights.0." + k, "light " + k, -40, 40, 1,
           (v) => first > 0 ? 10 * Math.log2((Array.isArray(v) ? v[0] : v) / first) : 0,
           (x) => scale(Math.pow(2, x / 10)), base);
  }
  const sm = ((sceneJson.render || {}).shadow_map) || {};
  slider(box, "render.shadow_map.resolution", "shadow map resolution", 4, 12, 1,
         (v) => Math.round(Math.log2(v)), (x) => 1 << x, sm.resolution ?? 2048);
  slider(box, "render.shadow_map.bias", "shadow map bias", 0, 100, 1,
         (v) => v > 0 ? 25 * Math.log10(v / 1e-5) : 0, (x) => x === 0 ? 0 : jsonNumber(1e-5 * Math.pow(10, x / 25)),
         sm.bias ?? 0.002);
  slider(box, "render.shadow_map.kernel", "PCF / PCSS kernel", 1, 15, 1, (v) => v, (x) => x,
         sm.kernel ?? 5);
  slider(box, "render.max_depth", "max depth", 0, 16, 1, (v) => v, (x) => x,
         (sceneJson.render || {}).max_depth ?? 5);
  buildEnvironmentControls(box);
}

// The environment (docs/viewer.md): a menu of the folder's maps, and, when there is one, its
// rotation and scale on sliders (environment.rotate, environment.scale).
let environmentFiles = [];  // from /api/scenes
const engines = {};  // name -> its capabilities (/api/engines)
function buildEnvironmentControls(box) {
  const own = sceneJson.environment;
  if (!own && environmentFiles.length === 0) return;
  const l = document.createElement("label");
  const menu = document.createElement("select");
  menu.id = "environment";
  const theirs = document.createElement("option");
  theirs.value = "";
  theirs.textContent = own ? "the scene's (" + own.file + ")" : "none";
  menu.appendChild(theirs);
  for (const f of environmentFiles) {
    const o = document.createElement("option");
    o.textContent = o.value = f;
    menu.appendChild(o);
  }
  const chosen = overrides.has("environment") ? JSON.parse(overrides.get("environment")) : null;
  if (chosen && chosen.file) menu.value = chosen.file;
  menu.addEventListener("change", () => {
    // The map replaces the whole key; its sliders' keys follow it, so they apply after it.
    for (const k of ["environment", "environment.rotate", "environment.scale"]) overrides.delete(k);
    if (menu.value) overrides.set("environment", JSON.stringify({ file: menu.value }));
    buildSliders();
    render();
  });
  l.append("environment ", menu);
  box.appendChild(l);
  const env = chosen || own;
  if (!env) return;
  slider(box, "environment.rotate", "environment rotate", -180, 180, 5, (v) => v, (x) => x,
         env.rotate ?? 0);
  // As the light's intensity: steps of 2^(1/10) from the scene's own (a colour keeps its tint).
  const base = env.scale ?? 1;
  const first = Array.isArray(base) ? base[0] : base;
  const scaled = (f) => Array.isArray(base) ? base.map((v) => jsonNumber(v * f)) : jsonNumber(base * f);
  slider(box, "environment.scale", "environment scale", -40, 40, 1,
         (v) => first > 0 ? 10 * Math.log2((Array.isArray(v) ? v[0] : v) / first) : 0,
         (x) => scaled(Math.pow(2, x / 10)), base);
}

$("material").addEventListener("change", buildMaterialSliders);
$("copy").addEventListener("click", () => navigator.clipboard && navigator.clipboard.writeText($("command").textContent));
for (const id of ["engine", "shading", "shadows", "spp", "sets", "aov", "abview", "bengine",
                  "bshading", "bshadows"])
  $(id).addEventListener(id === "spp" ? "input" : "change", () => {
    $("sppv").textContent = 1 << +$("spp").value;
    if (id === "spp") move(); else render();
  });
$("scene").addEventListener("change", async () => {
  camera = null;
  overrides.clear();
  await loadScene(false);
  render();
});

// The scene menu and the environment maps from the folder (/api/scenes).
async function listScenes() {
  const list = await (await backend.fetch("/api/scenes")).json();
  environmentFiles = list.environments || [];
  const chosen = $("scene").value;
  $("scene").textContent = "";
  for (const name of list.scenes) {
    const o = document.createElement("option");
    o.textContent = name;
    $("scene").appendChild(o);
  }
  if (chosen) choose("scene", chosen);
  return list;
}

// The visitor's own files (the web page: docs/web.md), chosen or dropped on the page: put in
// the scene folder by the backend, then the scene or model among them is shown: a scene file
// first, else a glTF, an OBJ or a PLY.
const sceneKinds = [/\.json$/i, /\.(gltf|glb)$/i, /\.obj$/i, /\.ply$/i];
async function openFiles(files) {
  if (!files || files.length === 0) return;
  let names;
  try {
    names = await backend.addFiles(files);
  } catch (e) {
    $("error").textContent = e.message;
    return;
  }
  const kind = (n) => sceneKinds.findIndex((k) => k.test(n));
  const main = names.filter((n) => kind(n) >= 0).sort((a, b) => kind(a) - kind(b))[0];
  if (!main) {
    $("error").textContent = names.join(", ") + ": no scene or model among them (.json, .gltf, .glb, .obj, .ply)";
    return;
  }
  await listScenes();
  choose("scene", main);
  $("scene").dispatchEvent(new Event("change"));
}
if (backend.addFiles) {
  $("files").classList.remove("hidden");
  $("file").addEventListener("change", () => openFiles($("file").files));
  document.addEventListener("dragover", (e) => e.preventDefault());
  document.addEventListener("drop", (e) => { e.preventDefault(); openFiles(e.dataTransfer.files); });
}

// Start: the scenes of the folder, then the view of the link. The server reads the link
// (/api/link) as it reads a request, every set= value as --set reads it: the page never
// parses a value of the query string itself. A link with a problem (a scene that is not
// there, an unknown engine) shows the page and its one-line error, and renders nothing
// until a control changes.
const choose = (id, value) => {  // selects `value` in the menu `id`, when it is one of its options
  const known = typeof value === "string" && [...$(id).options].some((o) => o.value === value);
  if (known) $(id).value = value;
  return known;
};
(async () => {
  try {
    if (backend.ready) await backend.ready;
    $("threads").textContent = backend.note || "";
    // The engines as the registry lists them (/api/engines), in both engine menus.
    for (const e of await (await backend.fetch("/api/engines")).json()) {
      engines[e.name] = e;
      for (const id of ["engine", "bengine"]) {
        const o = document.createElement("option");
        o.textContent = e.name;
        $(id).appendChild(o);
      }
    }
    const list = await listScenes();
    const link = await (await backend.fetch("/api/link" + location.search)).json();
    if (!choose("scene", link.scene)) $("scene").value = list.default || list.scenes[0] || "";
    choose("engine", link.engine);
    if (link.spp) $("spp").value = Math.round(Math.log2(link.spp));
    $("sppv").textContent = 1 << +$("spp").value;
    choose("aov", link.aov);
    choose("abview", link.ab);
    choose("bengine", link.b_engine);
    for (const s of link.b_sets) {
      if (s.key === "render.shading") choose("bshading", s.value);
      if (s.key === "render.shadows") choose("bshadows", s.value);
    }
    const rest = [];
    let position = null;
    const sliderKey = /^(lights\.0\.(position|intensity|irradiance|radiance)|render\.shadow_map\.(resolution|bias|kernel)|render\.max_depth|materials\.[^.]+\.(albedo|kd|base_color|shininess|roughness|metallic)|environment(\.(rotate|scale))?)$/;
    const point = (v) => Array.isArray(v) && v.length === 3 && v.every((x) => typeof x === "number");
    for (const s of link.sets) {
      if (s.key === "render.shading" && choose("shading", s.value)) continue;
      if (s.key === "render.shadows" && choose("shadows", s.value)) continue;
      if (s.key === "camera.position" && point(s.value)) position = s.value;
      else if (sliderKey.test(s.key)) overrides.set(s.key, JSON.stringify(s.value));
      else rest.push(s.text);
    }
    $("sets").value = rest.join("\n");
    if (link.error) {  // in the panel, and under the image where the eye is
      $("error").textContent = $("status").textContent = link.error;
      return;
    }
    await loadScene(false);
    if (position && camera) camera.position = position;
    move();  // the first image as a moving view's (fast), then the still one
  } catch (e) {
    $("error").textContent = "svetlo: error: the page could not start: " + e;
  }
})();
