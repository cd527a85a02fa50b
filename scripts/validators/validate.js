#!/usr/bin/env node
// Validates perclod's exports under output folders (scripts/validate_exports.sh
// runs it; see docs/validation.md):
//  * every .glb with the Khronos glTF-Validator (npm gltf-validator, JS API);
//  * every *tileset*.json with perclod's own structural 3D Tiles check
//    (checkTileset below) and, when a path to CesiumGS's 3d-tiles-validator
//    is given, with that too.
// Prints per file the errors/warnings/infos/hints and every message; exits 1
// when any file has an error or a warning, 2 on a usage error.
//
// Usage: node validate.js [--json FILE] [--tiles-validator MAIN_JS] FOLDER...
'use strict';

const fs = require('fs');
const path = require('path');
const os = require('os');
const { spawnSync } = require('child_process');
const gltfValidator = require('gltf-validator');

const SEVERITY = ['error', 'warning', 'info', 'hint'];

function usage(message) {
  if (message) console.error(`validate: ${message}`);
  console.error('usage: node validate.js [--json FILE] [--tiles-validator MAIN_JS] FOLDER...');
  process.exit(2);
}

function parseArgs(argv) {
  const args = { json: null, tilesValidator: null, folders: [] };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    if (a === '--json' || a === '--tiles-validator') {
      if (i + 1 >= argv.length) usage(`${a} needs a value`);
      args[a === '--json' ? 'json' : 'tilesValidator'] = argv[++i];
    } else if (a === '-h' || a === '--help') {
      usage();
    } else if (a.startsWith('-')) {
      usage(`unknown option ${a}`);
    } else {
      args.folders.push(a);
    }
  }
  if (args.folders.length === 0) usage('no output folder given');
  for (const f of args.folders) if (!fs.statSync(f, { throwIfNoEntry: false })?.isDirectory()) usage(`${f}: not a folder`);
  return args;
}

// Every file under dir (recursively, sorted) whose name passes keep.
function findFiles(dir, keep) {
  const found = [];
  const walk = (d) => {
    for (const e of fs.readdirSync(d, { withFileTypes: true }).sort((a, b) => a.name.localeCompare(b.name))) {
      const p = path.join(d, e.name);
      if (e.isDirectory()) {
        if (e.name !== 'node_modules' && !e.name.startsWith('.')) walk(p);
      } else if (keep(e.name)) {
        found.push(p);
      }
    }
  };
  walk(dir);
  return found;
}

function counts(messages) {
  const c = { errors: 0, warnings: 0, infos: 0, hints: 0 };
  for (const m of messages) c[`${m.severity}s`] += 1;
  return c;
}

// ---------------------------------------------------------------------------
// glTF-Validator

async function validateGlb(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await gltfValidator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0, // every issue
    writeTimestamp: false,
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)), (err, data) =>
          err ? reject(err.toString()) : resolve(new Uint8Array(data)));
      }),
  });
  const messages = report.issues.messages.map((m) => ({
    severity: SEVERITY[m.severity] ?? String(m.severity),
    code: m.code,
    message: m.message,
    pointer: m.pointer ?? (m.offset !== undefined ? `byte ${m.offset}` : ''),
  }));
  return {
    file,
    validator: 'glTF-Validator',
    errors: report.issues.numErrors,
    warnings: report.issues.numWarnings,
    infos: report.issues.numInfos,
    hints: report.issues.numHints,
    truncated: Boolean(report.issues.truncated),
    messages,
    info: report.info
      ? {
          version: report.info.version,
          generator: report.info.generator,
          extensionsUsed: report.info.extensionsUsed ?? [],
          drawCallCount: report.info.drawCallCount,
          totalVertexCount: report.info.totalVertexCount,
          totalTriangleCount: report.info.totalTriangleCount,
          materialCount: report.info.materialCount,
        }
      : null,
  };
}

// ---------------------------------------------------------------------------
// perclod's structural tileset check: what a 3D Tiles client needs to load
// and place the tileset, and perclod's own promises (docs/validation.md).

const mat4Identity = () => [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];

// Column-major 4x4 product a * b (glTF and 3D Tiles store matrices so).
function mat4Mul(a, b) {
  const r = new Array(16).fill(0);
  for (let c = 0; c < 4; ++c)
    for (let row = 0; row < 4; ++row)
      for (let k = 0; k < 4; ++k) r[c * 4 + row] += a[k * 4 + row] * b[c * 4 + k];
  return r;
}

function mat4Point(m, p) {
  return [0, 1, 2].map((a) => m[a] * p[0] + m[4 + a] * p[1] + m[8 + a] * p[2] + m[12 + a]);
}

// A glTF node's local matrix (matrix, or translation * rotation * scale).
function nodeMatrix(node) {
  if (Array.isArray(node.matrix)) return node.matrix.slice();
  const [tx, ty, tz] = node.translation ?? [0, 0, 0];
  const [x, y, z, w] = node.rotation ?? [0, 0, 0, 1];
  const [sx, sy, sz] = node.scale ?? [1, 1, 1];
  return [
    (1 - 2 * (y * y + z * z)) * sx, 2 * (x * y + z * w) * sx, 2 * (x * z - y * w) * sx, 0,
    2 * (x * y - z * w) * sy, (1 - 2 * (x * x + z * z)) * sy, 2 * (y * z + x * w) * sy, 0,
    2 * (x * z + y * w) * sz, 2 * (y * z - x * w) * sz, (1 - 2 * (x * x + y * y)) * sz, 0,
    tx, ty, tz, 1,
  ];
}

// The JSON chunk of a GLB, or throws.
function glbJson(file) {
  const b = fs.readFileSync(file);
  if (b.length < 20 || b.readUInt32LE(0) !== 0x46546c67) throw new Error('not a GLB (no glTF magic)');
  const length = b.readUInt32LE(12);
  if (b.readUInt32LE(16) !== 0x4e4f534a) throw new Error('first GLB chunk is not JSON');
  return JSON.parse(b.subarray(20, 20 + length).toString('utf8'));
}

// The corners of every POSITION accessor's min/max box, through the default
// scene's node transforms, in 3D Tiles' z-up frame (glTF y-up -> z-up:
// (x, y, z) -> (x, -z, y), what clients apply to glTF tile content).
function glbCorners(gltf) {
  const corners = [];
  const yUpToZUp = [1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1];
  const scene = gltf.scenes?.[gltf.scene ?? 0];
  const visit = (index, parent) => {
    const node = gltf.nodes[index];
    const m = mat4Mul(parent, nodeMatrix(node));
    if (node.mesh !== undefined) {
      for (const prim of gltf.meshes[node.mesh].primitives) {
        const acc = gltf.accessors[prim.attributes?.POSITION];
        if (!acc || !acc.min || !acc.max) continue;
        for (let i = 0; i < 8; ++i)
          corners.push(mat4Point(m, [0, 1, 2].map((a) => ((i >> a) & 1 ? acc.max[a] : acc.min[a]))));
      }
    }
    for (const c of node.children ?? []) visit(c, m);
  };
  for (const n of scene?.nodes ?? []) visit(n, yUpToZUp);
  return corners;
}

function invert3(m) {
  // m: columns u, v, w (each 3); returns rows of the inverse.
  const [a, b, c] = [m.slice(0, 3), m.slice(3, 6), m.slice(6, 9)];
  const cross = (p, q) => [p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]];
  const bc = cross(b, c), ca = cross(c, a), ab = cross(a, b);
  const det = a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2];
  if (Math.abs(det) < 1e-300) return null;
  return [bc, ca, ab].map((r) => r.map((x) => x / det));
}

// How far (in metres, 0 when inside) the points reach out of a volume.
function outside(volume, points) {
  let worst = 0;
  if (volume.box) {
    const b = volume.box;
    const inv = invert3(b.slice(3, 12));
    if (!inv) return Infinity;
    const scale = [0, 1, 2].map((k) => Math.hypot(b[3 + 3 * k], b[4 + 3 * k], b[5 + 3 * k]));
    for (const p of points) {
      const d = [p[0] - b[0], p[1] - b[1], p[2] - b[2]];
      for (let k = 0; k < 3; ++k) {
        const t = Math.abs(inv[k][0] * d[0] + inv[k][1] * d[1] + inv[k][2] * d[2]);
        worst = Math.max(worst, (t - 1) * scale[k]);
      }
    }
  } else if (volume.sphere) {
    const s = volume.sphere;
    for (const p of points) worst = Math.max(worst, Math.hypot(p[0] - s[0], p[1] - s[1], p[2] - s[2]) - s[3]);
  }
  return Math.max(0, worst);
}

function volumeCentre(volume) {
  if (volume.box) return volume.box.slice(0, 3);
  if (volume.sphere) return volume.sphere.slice(0, 3);
  return null;
}

const finite = (x) => typeof x === 'number' && Number.isFinite(x);
const finiteArray = (a, n) => Array.isArray(a) && a.length === n && a.every(finite);
// WGS84's semi-minor axis less 100 km: a centre nearer the Earth's centre
// than this is drawn deep inside the Earth by a globe client.
const INSIDE_EARTH_M = 6356752.3 - 100000;
// A placed model further than this above or below the ellipsoid is misplaced.
const OFF_SURFACE_M = 10000;

// ECEF metres -> [latitude deg, longitude deg, ellipsoidal height m] (WGS84).
function wgs84Geodetic([x, y, z]) {
  const a = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f);
  const lon = Math.atan2(y, x), p = Math.hypot(x, y);
  let lat = Math.atan2(z, p * (1 - e2)), h = 0;
  for (let i = 0; i < 10; ++i) {
    const n = a / Math.sqrt(1 - e2 * Math.sin(lat) ** 2);
    h = p / Math.cos(lat) - n;
    lat = Math.atan2(z, p * (1 - (e2 * n) / (n + h)));
  }
  return [(lat * 180) / Math.PI, (lon * 180) / Math.PI, h];
}

// Checks one tileset file; external tilesets it references are followed for
// placement and errors (each is also checked as a file of its own).
function checkTileset(file, externalTilesets) {
  const messages = [];
  const add = (severity, code, pointer, message) => messages.push({ severity, code, message, pointer });
  let tileset;
  try {
    tileset = JSON.parse(fs.readFileSync(file, 'utf8'));
  } catch (e) {
    add('error', 'JSON_INVALID', '', e.message);
    return messages;
  }
  if (!tileset.asset || !['1.0', '1.1'].includes(tileset.asset.version))
    add('error', 'ASSET_VERSION', '/asset/version', `asset.version is ${JSON.stringify(tileset.asset?.version)}, not "1.0" or "1.1"`);
  if (!finite(tileset.geometricError) || tileset.geometricError < 0)
    add('error', 'GEOMETRIC_ERROR_INVALID', '/geometricError', 'the tileset geometricError is not a number >= 0');
  if (!tileset.root) {
    add('error', 'ROOT_MISSING', '/root', 'the tileset has no root tile');
    return messages;
  }
  if (finite(tileset.geometricError) && finite(tileset.root.geometricError) && tileset.root.geometricError > tileset.geometricError)
    add('warning', 'TILESET_ERROR_BELOW_ROOT', '/geometricError',
      `the tileset geometricError ${tileset.geometricError} (the error of drawing none of it) is below its root tile's ${tileset.root.geometricError} (the error of drawing the root alone): drawing nothing would count as more accurate than the coarsest level`);
  if (!['ADD', 'REPLACE'].includes(tileset.root.refine))
    add('error', 'ROOT_REFINE', '/root/refine', `the root tile's refine is ${JSON.stringify(tileset.root.refine)}, not "ADD" or "REPLACE" (required at the root)`);

  const dir = path.dirname(file);
  const centres = []; // content tiles' volume centres in the outermost frame
  const walk = (tile, pointer, parentError, parentTransform, parentRefine) => {
    const refine = tile.refine ?? parentRefine;
    const vol = tile.boundingVolume;
    const kinds = vol ? ['box', 'region', 'sphere'].filter((k) => k in vol) : [];
    if (kinds.length === 0) add('error', 'BOUNDING_VOLUME_MISSING', `${pointer}/boundingVolume`, 'the tile has no box, region or sphere');
    else if (vol.box && !finiteArray(vol.box, 12)) add('error', 'BOUNDING_VOLUME_INVALID', `${pointer}/boundingVolume/box`, 'a box is 12 finite numbers');
    else if (vol.sphere && (!finiteArray(vol.sphere, 4) || vol.sphere[3] < 0)) add('error', 'BOUNDING_VOLUME_INVALID', `${pointer}/boundingVolume/sphere`, 'a sphere is 4 finite numbers, radius >= 0');
    else if (vol.region && !finiteArray(vol.region, 6)) add('error', 'BOUNDING_VOLUME_INVALID', `${pointer}/boundingVolume/region`, 'a region is 6 finite numbers');
    if (!finite(tile.geometricError) || tile.geometricError < 0) {
      add('error', 'GEOMETRIC_ERROR_INVALID', `${pointer}/geometricError`, 'geometricError is not a number >= 0');
    } else if (parentError !== null) {
      if (tile.geometricError > parentError)
        add('warning', 'GEOMETRIC_ERROR_ABOVE_PARENT', `${pointer}/geometricError`, `geometricError ${tile.geometricError} is above its parent's ${parentError}`);
      else if (tile.geometricError === parentError && parentRefine === 'REPLACE' && tile.content && !String(tile.content.uri ?? '').endsWith('.json'))
        add('warning', 'GEOMETRIC_ERROR_EQUALS_PARENT', `${pointer}/geometricError`,
          `geometricError ${tile.geometricError} equals its parent's: with REPLACE a client refines both at the same distance, so the parent's LOD is never shown on its own`);
    }
    if (tile.refine !== undefined && !['ADD', 'REPLACE'].includes(tile.refine))
      add('error', 'REFINE_INVALID', `${pointer}/refine`, `refine ${JSON.stringify(tile.refine)} is not "ADD" or "REPLACE"`);
    let transform = parentTransform;
    if (tile.transform !== undefined) {
      if (!finiteArray(tile.transform, 16)) add('error', 'TRANSFORM_INVALID', `${pointer}/transform`, 'a transform is 16 finite numbers');
      else transform = mat4Mul(parentTransform, tile.transform);
    }
    const content = tile.content;
    if (content !== undefined) {
      const uri = content.uri;
      if (typeof uri !== 'string' || uri === '') {
        add('error', 'CONTENT_URI_MISSING', `${pointer}/content/uri`, 'content has no uri');
      } else if (/^[a-z][a-z0-9+.-]*:/i.test(uri)) {
        add('info', 'CONTENT_URI_REMOTE', `${pointer}/content/uri`, `${uri} is not a local file: not checked`);
      } else {
        const target = path.resolve(dir, decodeURIComponent(uri));
        if (!fs.existsSync(target)) {
          add('error', 'CONTENT_MISSING', `${pointer}/content/uri`, `${uri}: no such file next to the tileset`);
        } else if (uri.toLowerCase().endsWith('.json')) {
          externalTilesets.add(target);
          try {
            const ext = JSON.parse(fs.readFileSync(target, 'utf8'));
            if (!ext.root) add('error', 'EXTERNAL_TILESET_INVALID', `${pointer}/content/uri`, `${uri} has no root tile`);
            else {
              if (finite(ext.geometricError) && finite(tile.geometricError) && ext.geometricError > tile.geometricError)
                add('warning', 'EXTERNAL_TILESET_ERROR', `${pointer}/content/uri`,
                  `${uri}'s geometricError ${ext.geometricError} is above the referencing tile's ${tile.geometricError}`);
              // The external root's box, through its own transform, in this
              // tile's frame, must lie in this tile's volume.
              const extTransform = finiteArray(ext.root.transform, 16) ? ext.root.transform : mat4Identity();
              if (vol && !vol.region && ext.root.boundingVolume) {
                const inner = ext.root.boundingVolume.box ?? null;
                if (inner) {
                  const pts = [];
                  for (let i = 0; i < 8; ++i) {
                    const p = inner.slice(0, 3);
                    for (let k = 0; k < 3; ++k) {
                      const s = (i >> k) & 1 ? 1 : -1;
                      for (let a = 0; a < 3; ++a) p[a] += s * inner[3 + 3 * k + a];
                    }
                    pts.push(mat4Point(extTransform, p));
                  }
                  const out = outside(vol, pts);
                  if (out > 1e-4 * Math.max(1, Math.hypot(...inner.slice(3, 12))) + 1e-3)
                    add('warning', 'EXTERNAL_TILESET_OUTSIDE_VOLUME', `${pointer}/boundingVolume`,
                      `${uri}'s root box reaches ${out.toPrecision(4)} m out of this tile's bounding volume`);
                }
              }
              const c = ext.root.boundingVolume && volumeCentre(ext.root.boundingVolume);
              if (c) {
                centres.push({ pointer: `${pointer} -> ${uri}`, centre: mat4Point(mat4Mul(transform, extTransform), c) });
              }
            }
          } catch (e) {
            add('error', 'EXTERNAL_TILESET_INVALID', `${pointer}/content/uri`, `${uri}: ${e.message}`);
          }
        } else if (uri.toLowerCase().endsWith('.glb')) {
          try {
            const corners = glbCorners(glbJson(target));
            if (vol && !vol.region && corners.length) {
              const out = outside(vol, corners);
              const size = vol.box ? Math.hypot(...vol.box.slice(3, 12)) : vol.sphere[3];
              if (out > 1e-4 * Math.max(1, size) + 1e-3)
                add('error', 'CONTENT_OUTSIDE_VOLUME', `${pointer}/boundingVolume`,
                  `${uri}'s geometry (its POSITION min/max through its nodes, y-up to z-up) reaches ${out.toPrecision(4)} m out of the tile's bounding volume: clients cull or place it wrongly`);
            }
          } catch (e) {
            add('error', 'CONTENT_INVALID', `${pointer}/content/uri`, `${uri}: ${e.message}`);
          }
          const c = vol && volumeCentre(vol);
          if (c) centres.push({ pointer, centre: mat4Point(transform, c) });
        }
      }
    }
    (tile.children ?? []).forEach((child, i) =>
      walk(child, `${pointer}/children/${i}`, finite(tile.geometricError) ? tile.geometricError : null, transform, refine));
  };
  walk(tileset.root, '/root', null, mat4Identity(), null);

  // Placement: a tileset is drawn in ECEF metres; content whose centre is
  // deep inside the Earth was not georeferenced (no transform, local or
  // projected coordinates). Reported once per tileset, as information: the
  // format allows it, but a globe client shows nothing there.
  const inside = centres.filter((c) => Math.hypot(...c.centre) < INSIDE_EARTH_M);
  const placed = centres.filter((c) => Math.hypot(...c.centre) >= INSIDE_EARTH_M);
  if (placed.length) {
    // Where the first content lands (WGS84), to compare with the source
    // CRS's position (e.g. PROJ's cs2cs); far from the surface is a warning.
    const [lat, lon, h] = wgs84Geodetic(placed[0].centre);
    add('info', 'PLACEMENT', placed[0].pointer,
      `content volume centred at latitude ${lat.toFixed(7)}, longitude ${lon.toFixed(7)}, ${h.toFixed(2)} m above the WGS84 ellipsoid`);
    for (const c of placed) {
      const [, , hc] = wgs84Geodetic(c.centre);
      if (Math.abs(hc) > OFF_SURFACE_M) {
        add('warning', 'PLACED_OFF_THE_SURFACE', c.pointer,
          `content volume centred ${(hc / 1000).toFixed(1)} km ${hc > 0 ? 'above' : 'below'} the WGS84 ellipsoid: the transform and the coordinates do not agree`);
        break;
      }
    }
  }
  if (inside.length) {
    const r = Math.max(...inside.map((c) => Math.hypot(...c.centre)));
    add('info', 'NOT_GEOREFERENCED', inside[0].pointer,
      `${inside.length} of ${centres.length} content volumes are centred within ${(r / 1000).toFixed(1)} km of the Earth's centre (no transform to ECEF; coordinates taken as ECEF metres): a globe client such as CesiumJS draws them inside the Earth`);
  }
  return messages;
}

// ---------------------------------------------------------------------------
// CesiumGS 3d-tiles-validator (optional; a path to its main.js or bin/main)

function runTilesValidator(mainJs, file) {
  const report = path.join(fs.mkdtempSync(path.join(os.tmpdir(), 'tiles-validator-')), 'report.json');
  const r = spawnSync(process.execPath, [mainJs, '--tilesetFile', file, '--reportFile', report], {
    encoding: 'utf8',
    maxBuffer: 64 << 20,
  });
  if (!fs.existsSync(report)) {
    return {
      failed: `3d-tiles-validator wrote no report (exit ${r.status}): ${(r.stderr || r.stdout || '').trim().split('\n').slice(-3).join(' / ')}`,
    };
  }
  const rep = JSON.parse(fs.readFileSync(report, 'utf8'));
  fs.rmSync(path.dirname(report), { recursive: true, force: true });
  const messages = [];
  const flatten = (issues, prefix) => {
    for (const i of issues ?? []) {
      messages.push({
        severity: String(i.severity).toLowerCase(),
        code: i.type,
        message: i.message,
        pointer: prefix ? `${prefix}: ${i.path}` : i.path,
      });
      flatten(i.causes, prefix ? `${prefix} > ${i.path}` : i.path);
    }
  };
  flatten(rep.issues, '');
  return {
    errors: rep.numErrors ?? 0,
    warnings: rep.numWarnings ?? 0,
    infos: rep.numInfos ?? 0,
    messages,
  };
}

function tilesValidatorVersion(mainJs) {
  // main.js lives in build/ (or src/ via ts-node): the package.json is above.
  for (let d = path.dirname(path.resolve(mainJs)); d !== path.dirname(d); d = path.dirname(d)) {
    const p = path.join(d, 'package.json');
    if (fs.existsSync(p)) {
      const pkg = JSON.parse(fs.readFileSync(p, 'utf8'));
      if (pkg.name === '3d-tiles-validator') return pkg.version;
    }
  }
  return 'unknown';
}

// ---------------------------------------------------------------------------

function printResult(r, label) {
  const c = [`${r.errors} errors`, `${r.warnings} warnings`, `${r.infos} infos`];
  if (r.hints !== undefined) c.push(`${r.hints} hints`);
  console.log(`  ${label} ${r.file}: ${c.join(', ')}`);
  for (const m of r.messages)
    console.log(`    ${m.severity.toUpperCase()} ${m.code}${m.pointer ? ` at ${m.pointer}` : ''}: ${m.message}`);
  if (r.truncated) console.log('    (the validator truncated its list of messages)');
}

async function main() {
  const args = parseArgs(process.argv.slice(2));
  if (args.tilesValidator && !fs.existsSync(args.tilesValidator)) usage(`${args.tilesValidator}: no such file`);
  const summary = {
    date: new Date().toISOString(),
    validators: {
      'gltf-validator': gltfValidator.version(),
      'perclod-tileset-check': require('./package.json').version,
      '3d-tiles-validator': args.tilesValidator ? tilesValidatorVersion(args.tilesValidator) : null,
    },
    folders: [],
    failed: false,
  };
  console.log(`glTF-Validator ${summary.validators['gltf-validator']}; 3d-tiles-validator ${summary.validators['3d-tiles-validator'] ?? 'not given (step skipped)'}`);
  for (const folder of args.folders) {
    const entry = { folder, glb: [], tilesets: [], totals: {} };
    console.log(`${folder}:`);
    for (const file of findFiles(folder, (n) => n.toLowerCase().endsWith('.glb'))) {
      let r;
      try {
        r = await validateGlb(file);
      } catch (e) {
        r = { file, validator: 'glTF-Validator', errors: 1, warnings: 0, infos: 0, hints: 0,
          messages: [{ severity: 'error', code: 'VALIDATOR_FAILED', message: String(e), pointer: '' }] };
      }
      printResult(r, 'glb');
      entry.glb.push(r);
    }
    const tilesetFiles = findFiles(folder, (n) => /tileset.*\.json$/i.test(n));
    const external = new Set();
    const structural = tilesetFiles.map((f) => ({ file: f, messages: checkTileset(f, external) }));
    for (const { file, messages } of structural) {
      const t = { file, external: external.has(path.resolve(file)), check: { file, ...counts(messages), messages } };
      printResult(t.check, 'tileset (perclod check)');
      if (args.tilesValidator) {
        const v = runTilesValidator(args.tilesValidator, file);
        if (v.failed) {
          t.tilesValidator = { file, errors: 1, warnings: 0, infos: 0,
            messages: [{ severity: 'error', code: 'VALIDATOR_FAILED', message: v.failed, pointer: '' }] };
        } else {
          t.tilesValidator = { file, ...v };
        }
        printResult(t.tilesValidator, 'tileset (3d-tiles-validator)');
      }
      entry.tilesets.push(t);
    }
    if (tilesetFiles.length && !args.tilesValidator)
      console.log('  note: 3d-tiles-validator step skipped (give --tiles-validator MAIN_JS or TILES_VALIDATOR=...; docs/validation.md)');
    const sum = (list) => list.reduce((s, r) => ({
      files: s.files + 1, errors: s.errors + r.errors, warnings: s.warnings + r.warnings, infos: s.infos + r.infos,
    }), { files: 0, errors: 0, warnings: 0, infos: 0 });
    entry.totals = {
      glb: sum(entry.glb),
      tileset_check: sum(entry.tilesets.map((t) => t.check)),
      tiles_validator: args.tilesValidator ? sum(entry.tilesets.map((t) => t.tilesValidator)) : null,
    };
    const bad = (s) => s && (s.errors > 0 || s.warnings > 0);
    entry.failed = bad(entry.totals.glb) || bad(entry.totals.tileset_check) || bad(entry.totals.tiles_validator);
    if (entry.glb.length === 0) console.log('  note: no .glb files here');
    console.log(`  ${entry.failed ? 'FAIL' : 'ok'}: ${entry.totals.glb.files} GLB (${entry.totals.glb.errors} errors, ${entry.totals.glb.warnings} warnings), ` +
      `${tilesetFiles.length} tilesets`);
    summary.failed ||= entry.failed;
    summary.folders.push(entry);
  }
  if (args.json) fs.writeFileSync(args.json, JSON.stringify(summary, null, 2) + '\n');
  process.exit(summary.failed ? 1 : 0);
}

main().catch((e) => {
  console.error(`validate: ${e.stack || e}`);
  process.exit(2);
});
