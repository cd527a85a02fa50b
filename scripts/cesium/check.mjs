// The CesiumJS check of perclod's 3D Tiles exports (scripts/check_cesium.sh
// runs it; docs/clients.md says what it checks and why).
//
// node check.mjs [options] OUTPUT_FOLDER [more folders]
//   --json FILE       write the results as JSON
//   --shots DIR       where the screenshots go (default: a new /tmp/check_cesium.* folder)
//   --chromium PATH   the browser (default: Debian's /usr/lib/chromium/chromium)
//   --timeout S       seconds one view may take to load (default 60)
//   --force-unlit     draw every LOD unlit (Cesium's UNLIT lighting model): the
//                     shading check must then fail; a test of the check itself
//
// Serves the folders and Cesium's built files on 127.0.0.1, opens every
// <model>_tileset.json found (with its <model>_manifest.json) in CesiumJS in
// headless Chromium (WebGL through SwiftShader), and for each LOD stands the
// camera inside the distances it serves and at 0.9x and 1.1x of each switch
// distance. Exit status: 0 all passed, 1 a check failed, 2 the check could not run.
import fs from "node:fs";
import http from "node:http";
import path from "node:path";
import { fileURLToPath } from "node:url";
import puppeteer from "puppeteer-core";

const here = path.dirname(fileURLToPath(import.meta.url));
const cesiumBuild = path.join(here, "node_modules", "cesium", "Build", "Cesium");

// The fixed light of every view's screenshot (the sun's place would otherwise
// depend on the clock and on where the tileset is on the Earth): from the
// south-south-west, 35 degrees up. The shading check relights the oblique
// views from their left and their right at the same elevation.
const LIGHT = { azimuth: 200, elevation: 35 };
const RELIGHT = { elevation: 35 };
const FACADE_AZIMUTH = 180; // standing south of the box, looking north
const OBLIQUE_AZIMUTH = 225; // south-west of it, looking north-east

// Pass limits (docs/clients.md#what-passes).
const MIN_MODEL_PIXELS = 200; // a drawn model covers at least this many pixels...
const MIN_BOX_FRACTION = 0.05; // ...and this share of its box's face as projected
const MAX_OUTSIDE_BOX = 0.005; // model pixels outside the projected bounding box
const DISTANCE_TOLERANCE = 1e-3; // Cesium's distance to the root's box vs the planned one
const MIN_SHADE_SPREAD = 10; // relit: grey levels between the 5th and 95th percentile of the change

class UsageError extends Error {}
const usedShotDirs = new Set();

function parseArgs(argv) {
  const o = { folders: [], json: null, shots: null, chromium: null, timeout: 60, forceUnlit: false };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    const value = () => {
      if (i + 1 >= argv.length) throw new UsageError(`${a} needs a value`);
      return argv[++i];
    };
    if (a === "--json") o.json = value();
    else if (a === "--shots") o.shots = value();
    else if (a === "--chromium") o.chromium = value();
    else if (a === "--timeout") o.timeout = Number(value());
    else if (a === "--force-unlit") o.forceUnlit = true;
    else if (a === "-h" || a === "--help") o.help = true;
    else if (a.startsWith("-")) throw new UsageError(`unknown option ${a}`);
    else o.folders.push(a);
  }
  if (!o.help && !o.folders.length) throw new UsageError("no output folder given");
  if (!(o.timeout > 0)) throw new UsageError("--timeout takes a number of seconds");
  return o;
}

// Every model in a folder (or one level down: a batch's per-model folders)
// with a manifest whose files name a tileset.
function findModels(folder, index) {
  const found = [];
  const visit = (dir, depth) => {
    for (const e of fs.readdirSync(dir, { withFileTypes: true }).sort((a, b) => a.name.localeCompare(b.name))) {
      const p = path.join(dir, e.name);
      if (e.isDirectory() && depth < 1) visit(p, depth + 1);
      else if (e.isFile() && e.name.endsWith("_manifest.json")) {
        let manifest;
        try {
          manifest = JSON.parse(fs.readFileSync(p, "utf8"));
        } catch (err) {
          throw new Error(`${p}: not JSON: ${err.message}`);
        }
        const tilesetName = manifest.files && manifest.files.tileset;
        if (!tilesetName) continue; // exported without `tileset: true`
        const tilesetPath = path.join(dir, tilesetName);
        if (!fs.existsSync(tilesetPath)) throw new Error(`${p} names ${tilesetName}, which is not in ${dir}`);
        const rel = path.relative(folder, dir).split(path.sep).filter(Boolean).map(encodeURIComponent);
        found.push({
          folder,
          manifestPath: p,
          manifest,
          tilesetPath,
          tileset: JSON.parse(fs.readFileSync(tilesetPath, "utf8")),
          url: ["", "out", String(index), ...rel, encodeURIComponent(tilesetName)].join("/"),
        });
      }
    }
  };
  visit(folder, 0);
  return found;
}

const fmt = (x) => (Math.round(x * 10) / 10).toString();

// The views of one model: for each LOD a distance inside what it serves,
// and 0.9x and 1.1x of every switch distance; each from the south facade
// and from the south-west corner (the oblique one also checks shading).
function planViews(manifest) {
  const lods = [...manifest.lods].sort((a, b) => a.serves.from - b.serves.from);
  const serving = (d) => {
    let best = lods[0];
    for (const l of lods) if (d >= l.serves.from) best = l;
    return best;
  };
  const points = [];
  lods.forEach((l, i) => {
    const to = l.serves.to;
    const d = to === null || to === undefined ? l.serves.from * 1.2 : 0.5 * (l.serves.from + to);
    points.push({ distance: d, why: `inside ${fmt(l.serves.from)}-${to == null ? "" : fmt(to)} m` });
    if (i > 0) {
      points.push({ distance: 0.9 * l.serves.from, why: `0.9x switch ${fmt(l.serves.from)} m` });
      points.push({ distance: 1.1 * l.serves.from, why: `1.1x switch ${fmt(l.serves.from)} m` });
    }
  });
  points.sort((a, b) => a.distance - b.distance);
  const views = [];
  for (const p of points) {
    const expected = serving(p.distance);
    for (const [kind, azimuth] of [["facade", FACADE_AZIMUTH], ["oblique", OBLIQUE_AZIMUTH]]) {
      views.push({
        ...p,
        kind,
        azimuth,
        expected: expected.glb,
        expected_lod_distance: expected.distance,
      });
    }
  }
  return views;
}

// The JSON chunk of a GLB.
function glbJson(file) {
  const b = fs.readFileSync(file);
  if (b.length < 20 || b.readUInt32LE(0) !== 0x46546c67 || b.readUInt32LE(16) !== 0x4e4f534a) {
    throw new Error(`${file}: not a GLB with a JSON chunk`);
  }
  return JSON.parse(b.subarray(20, 20 + b.readUInt32LE(12)).toString("utf8"));
}

// What a renderer needs to light the content the way perclod means it,
// read from each tile's GLB: every primitive has normals, and no material is
// metallic (glTF's metallicFactor is 1 when absent: a PBR client such as
// CesiumJS then draws the surface as rough metal, with no diffuse light, so
// its brightness follows the view direction, not the light's).
function checkContents(model) {
  const dir = path.dirname(model.tilesetPath);
  const out = { glbs: [], problems: [] };
  for (let tile = model.tileset.root; tile; tile = (tile.children || [])[0]) {
    const uri = tile.content && tile.content.uri;
    if (!uri || !uri.endsWith(".glb")) continue;
    const j = glbJson(path.join(dir, decodeURIComponent(uri)));
    let primitives = 0;
    let withoutNormals = 0;
    for (const mesh of j.meshes || []) {
      for (const p of mesh.primitives || []) {
        ++primitives;
        if (!p.attributes || p.attributes.NORMAL === undefined) ++withoutNormals;
      }
    }
    const metallic = (j.materials || [])
      .map((m) => ({ name: m.name || "(unnamed)", metallic: (m.pbrMetallicRoughness || {}).metallicFactor ?? 1.0 }))
      .filter((m) => m.metallic > 0);
    out.glbs.push({ glb: uri, primitives, without_normals: withoutNormals, materials: (j.materials || []).length,
      metallic_materials: metallic });
    if (withoutNormals) out.problems.push(`${uri}: ${withoutNormals} of ${primitives} primitives have no NORMAL (drawn unlit)`);
  }
  const metallicGlbs = out.glbs.filter((g) => g.metallic_materials.length);
  if (metallicGlbs.length) {
    const names = [...new Set(metallicGlbs.flatMap((g) => g.metallic_materials.map((m) => `"${m.name}" ${m.metallic}`)))];
    out.problems.push(`metallic materials in ${metallicGlbs.length} of ${out.glbs.length} GLBs (metallicFactor ` +
      `${names.slice(0, 4).join(", ")}${names.length > 4 ? ", ..." : ""}; absent means 1): CesiumJS draws them as ` +
      `rough metal, lit by reflection only, where perclod renders matte colours (metallicFactor 0)`);
  }
  return out;
}

function contentType(file) {
  const types = {
    ".html": "text/html; charset=utf-8", ".js": "text/javascript; charset=utf-8", ".mjs": "text/javascript",
    ".css": "text/css", ".json": "application/json", ".glb": "model/gltf-binary", ".gltf": "model/gltf+json",
    ".png": "image/png", ".jpg": "image/jpeg", ".svg": "image/svg+xml", ".wasm": "application/wasm",
    ".bin": "application/octet-stream", ".ktx2": "image/ktx2", ".xml": "application/xml",
  };
  return types[path.extname(file).toLowerCase()] || "application/octet-stream";
}

// A static server on 127.0.0.1: / is this folder's page, /cesium/ Cesium's
// built files, /out/<i>/ the i-th output folder. Nothing outside them.
function serve(folders) {
  const roots = { cesium: cesiumBuild };
  folders.forEach((f, i) => (roots[`out/${i}`] = f));
  const pageFiles = { "/": "page.html", "/page.html": "page.html", "/page.js": "page.js" };
  const server = http.createServer((req, res) => {
    const url = new URL(req.url, "http://127.0.0.1");
    let file = null;
    const pathname = decodeURIComponent(url.pathname);
    if (pageFiles[pathname]) file = path.join(here, pageFiles[pathname]);
    else {
      for (const [prefix, root] of Object.entries(roots)) {
        if (pathname.startsWith(`/${prefix}/`)) {
          const p = path.resolve(root, "." + pathname.slice(prefix.length + 1));
          if (p.startsWith(path.resolve(root) + path.sep)) file = p;
        }
      }
    }
    if (!file || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
      res.writeHead(404, { "content-type": "text/plain" });
      res.end("not found\n");
      return;
    }
    res.writeHead(200, { "content-type": contentType(file), "cache-control": "no-store" });
    fs.createReadStream(file).pipe(res);
  });
  return new Promise((resolve, reject) => {
    server.on("error", reject);
    server.listen(0, "127.0.0.1", () => resolve(server));
  });
}

function chromiumPath(given) {
  const candidates = given ? [given] : ["/usr/lib/chromium/chromium", "/usr/bin/chromium"];
  for (const c of candidates) if (fs.existsSync(c)) return c;
  throw new Error(`no chromium at ${candidates.join(" or ")} (Debian: apt-get install chromium)`);
}

function savePng(dataUrl, file) {
  fs.writeFileSync(file, Buffer.from(dataUrl.slice(dataUrl.indexOf(",") + 1), "base64"));
}

async function checkModel(browser, origin, model, o, shotsRoot) {
  const m = model.manifest;
  const name = (m.model && m.model.name) || path.basename(model.manifestPath, "_manifest.json");
  // Each model's screenshots in a folder of its own (two folders may hold
  // models of the same name).
  let shots = path.join(shotsRoot, name);
  for (let k = 2; usedShotDirs.has(shots); ++k) shots = path.join(shotsRoot, `${name}-${k}`);
  usedShotDirs.add(shots);
  fs.mkdirSync(shots, { recursive: true });
  const display = m.display || {};
  const extras = (((model.tileset.asset || {}).extras || {}).perclod) || {};
  const problems = [];
  const width = display.width;
  const height = display.height;
  const fovYDeg = display.fov_y_deg;
  if (!(width > 0 && height > 0 && fovYDeg > 0)) throw new Error(`${model.manifestPath}: display has no width, height and fov_y_deg`);
  const mse = extras.maximum_screen_space_error;
  if (!(mse > 0)) throw new Error(`${model.tilesetPath}: asset.extras.perclod.maximum_screen_space_error is missing`);
  if (extras.display && extras.display.height_px !== height) {
    problems.push(`tileset display height ${extras.display.height_px} px is not the manifest's ${height} px`);
  }
  const contents = checkContents(model);
  problems.push(...contents.problems);
  const box = model.tileset.root && model.tileset.root.boundingVolume && model.tileset.root.boundingVolume.box;
  if (!box) throw new Error(`${model.tilesetPath}: the root has no bounding box`);

  const page = await browser.newPage();
  await page.setViewport({ width, height, deviceScaleFactor: 1 });
  const consoleErrors = [];
  const consoleWarnings = [];
  const blocked = [];
  await page.setRequestInterception(true);
  page.on("request", (req) => {
    const u = req.url();
    if (u.startsWith(origin + "/") || u.startsWith("data:") || u.startsWith("blob:")) req.continue();
    else {
      blocked.push(u);
      req.abort("blockedbyclient");
    }
  });
  page.on("console", (msg) => {
    if (msg.type() === "error") consoleErrors.push(msg.text());
    else if (msg.type() === "warn" || msg.type() === "warning") consoleWarnings.push(msg.text());
  });
  page.on("pageerror", (err) => consoleErrors.push(`uncaught: ${err.message}`));
  page.on("requestfailed", (req) => {
    if (!blocked.includes(req.url())) consoleErrors.push(`request failed: ${req.url()} (${req.failure()?.errorText})`);
  });
  page.on("response", (res) => {
    if (res.status() >= 400) consoleErrors.push(`HTTP ${res.status()}: ${res.url()}`);
  });

  await page.goto(`${origin}/page.html`, { waitUntil: "load" });
  const setup = await page.evaluate((args) => window.perclodSetup(args), {
    url: origin + model.url,
    fovYDeg,
    maximumScreenSpaceError: mse,
    box,
    light: LIGHT,
    forceUnlit: o.forceUnlit,
  });
  if (setup.drawing_buffer[0] !== width || setup.drawing_buffer[1] !== height) {
    problems.push(`drawing buffer ${setup.drawing_buffer.join("x")} is not the display's ${width}x${height}`);
  }
  if (Math.abs(setup.fov_y_deg - fovYDeg) > 1e-6) problems.push(`Cesium's vertical fov ${setup.fov_y_deg} is not ${fovYDeg}`);
  if (setup.pixel_ratio !== 1) problems.push(`Cesium's pixel ratio is ${setup.pixel_ratio}, not 1`);

  const views = planViews(m);
  const results = [];
  for (const v of views) {
    const started = Date.now();
    const r = await page.evaluate((args) => window.perclodView(args), {
      distance: v.distance,
      azimuth: v.azimuth,
      timeoutMs: o.timeout * 1000,
      relight: v.kind === "oblique" ? RELIGHT : null,
    });
    r.view_ms = Date.now() - started;
    const tag = `${v.kind}_${fmt(v.distance)}m`;
    const shot = path.join(shots, `${tag}.png`);
    savePng(r.png, shot);
    delete r.png;
    const fails = [];
    if (r.timed_out) fails.push(`not loaded after ${o.timeout} s`);
    if (r.drawn.length !== 1 || r.drawn[0] !== v.expected) {
      fails.push(`drew ${r.drawn.length ? r.drawn.join(" + ") : "nothing"}, the manifest says ${v.expected}`);
    }
    const minPixels = Math.max(MIN_MODEL_PIXELS, MIN_BOX_FRACTION * Math.min(r.box_face_pixels, r.viewport_pixels));
    if (r.model_pixels < minPixels) {
      fails.push(`blank: ${r.model_pixels} model pixels, fewer than ${Math.round(minPixels)}`);
    }
    if (r.pixels_outside_box !== null && r.pixels_outside_box > MAX_OUTSIDE_BOX * Math.max(1, r.model_pixels)) {
      fails.push(`misplaced: ${r.pixels_outside_box} of ${r.model_pixels} model pixels are outside the tileset's bounding box`);
    }
    if (Math.abs(r.cesium_distance - v.distance) > DISTANCE_TOLERANCE * v.distance) {
      fails.push(`Cesium's distance to the bounding box is ${r.cesium_distance.toFixed(2)} m, not ${v.distance.toFixed(2)} m`);
    }
    if (r.relight && !(r.relight.spread >= MIN_SHADE_SPREAD)) {
      fails.push(`no shading: lit from the left and then the right, the model's pixels changed by ` +
        `${r.relight.delta_p05.toFixed(1)} to ${r.relight.delta_p95.toFixed(1)} grey levels (5th-95th percentile), ` +
        `a spread under ${MIN_SHADE_SPREAD}: faces of different orientation are not shaded differently`);
    }
    results.push({ ...v, ...r, screenshot: shot, pass: fails.length === 0, failures: fails });
  }
  await page.close();
  if (consoleErrors.length) problems.push(`browser console: ${consoleErrors.length} error(s): ${consoleErrors.slice(0, 5).join(" | ")}`);
  if (blocked.length) problems.push(`requests to other hosts blocked: ${blocked.slice(0, 5).join(", ")}`);
  return {
    model: name,
    tileset: model.tilesetPath,
    manifest: model.manifestPath,
    display: { width, height, fov_y_deg: fovYDeg },
    maximum_screen_space_error: mse,
    root_transform: model.tileset.root.transform || null,
    setup,
    contents: contents.glbs,
    views: results,
    console_errors: consoleErrors,
    console_warnings: consoleWarnings,
    blocked_requests: blocked,
    problems,
    pass: problems.length === 0 && results.every((r) => r.pass),
  };
}

function printTable(model) {
  const rows = [["view", "distance m", "why", "expected", "drawn", "Cesium dist m", "model px", "shading", "pass"]];
  for (const r of model.views) {
    const shading = r.relight ? `${r.relight.spread.toFixed(0)} levels` : "";
    rows.push([r.kind, r.distance.toFixed(1), r.why, r.expected, r.drawn.join("+") || "-",
      r.cesium_distance.toFixed(1), String(r.model_pixels), shading, r.pass ? "yes" : "NO"]);
  }
  const widths = rows[0].map((_, c) => Math.max(...rows.map((row) => row[c].length)));
  console.log(`${model.model}: ${model.tileset}`);
  console.log(`  display ${model.display.width}x${model.display.height}, fov_y ${model.display.fov_y_deg.toFixed(3)} deg, ` +
    `maximumScreenSpaceError ${model.maximum_screen_space_error}, ${model.root_transform ? "root transform" : "no root transform: coordinates as ECEF"}; ` +
    `CesiumJS ${model.setup.cesium}, ${model.setup.webgl} on ${model.setup.renderer}`);
  for (const row of rows) console.log("  " + row.map((cell, c) => cell.padEnd(widths[c])).join("  "));
  for (const p of model.problems) console.log(`  problem: ${p}`);
  for (const r of model.views) for (const f of r.failures) console.error(`check_cesium: ${model.model} ${r.kind} at ${r.distance.toFixed(1)} m: ${f}`);
  for (const p of model.problems) console.error(`check_cesium: ${model.model}: ${p}`);
}

async function main() {
  let o;
  try {
    o = parseArgs(process.argv.slice(2));
  } catch (err) {
    if (err instanceof UsageError) {
      console.error(`check_cesium: ${err.message} (--help for usage)`);
      return 2;
    }
    throw err;
  }
  if (o.help) {
    const text = fs.readFileSync(fileURLToPath(import.meta.url), "utf8").split("\n");
    console.log(text.slice(3, 11).map((l) => l.replace(/^\/\/ ?/, "")).join("\n"));
    return 0;
  }
  if (!fs.existsSync(path.join(cesiumBuild, "Cesium.js"))) {
    console.error(`check_cesium: ${cesiumBuild}/Cesium.js is missing: run npm ci in ${here}`);
    return 2;
  }
  const folders = o.folders.map((f) => path.resolve(f));
  const models = [];
  for (let i = 0; i < folders.length; ++i) {
    if (!fs.existsSync(folders[i]) || !fs.statSync(folders[i]).isDirectory()) {
      console.error(`check_cesium: ${o.folders[i]}: no such folder`);
      return 2;
    }
    const found = findModels(folders[i], i);
    if (!found.length) {
      console.error(`check_cesium: ${o.folders[i]}: no <model>_manifest.json naming a tileset (export with tileset: true)`);
      return 2;
    }
    models.push(...found);
  }
  const shots = path.resolve(o.shots || fs.mkdtempSync("/tmp/check_cesium."));
  fs.mkdirSync(shots, { recursive: true });

  const t0 = Date.now();
  const server = await serve(folders);
  const origin = `http://127.0.0.1:${server.address().port}`;
  const browser = await puppeteer.launch({
    executablePath: chromiumPath(o.chromium),
    headless: true,
    args: ["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist",
      "--hide-scrollbars", "--mute-audio"],
  });
  const report = { cesium_version: null, models: [], seconds: 0, pass: false, shots };
  let status = 0;
  try {
    for (const model of models) {
      const r = await checkModel(browser, origin, model, o, shots);
      report.cesium_version = r.setup.cesium;
      report.models.push(r);
      printTable(r);
      if (!r.pass) status = 1;
    }
  } finally {
    await browser.close();
    server.close();
  }
  report.seconds = (Date.now() - t0) / 1000;
  report.pass = status === 0;
  if (o.json) fs.writeFileSync(o.json, JSON.stringify(report, null, 2) + "\n");
  const views = report.models.reduce((n, m) => n + m.views.length, 0);
  const passed = report.models.reduce((n, m) => n + m.views.filter((v) => v.pass).length, 0);
  console.log(`check_cesium: ${status === 0 ? "OK" : "FAILED"}: ${passed} of ${views} views passed on ${report.models.length} ` +
    `model(s) in ${report.seconds.toFixed(1)} s; screenshots in ${shots}${o.json ? `; results in ${o.json}` : ""}`);
  // The plain count test runners close with (scripts/test.sh adds it up):
  // each view, and each model's problems outside the views as one check.
  const modelChecks = report.models.length;
  const modelFailed = report.models.filter((m) => m.problems.length).length;
  console.log(`${passed + modelChecks - modelFailed} passed, ${views - passed + modelFailed} failed`);
  return status;
}

main().then(
  (code) => process.exit(code),
  (err) => {
    console.error(`check_cesium: ${err && err.stack ? err.stack : err}`);
    process.exit(2);
  },
);
