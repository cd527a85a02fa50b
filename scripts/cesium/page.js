// Browser side of scripts/check_cesium.sh (driven by check.mjs through
// puppeteer): a CesiumJS scene with no globe, imagery, sky or terrain, so
// nothing is fetched but the tileset and Cesium's own files from 127.0.0.1.
// window.perclodSetup(options) loads one tileset with the refinement settings
// of the display profile it was made for; window.perclodView(view) puts the
// camera at a distance from the tileset's bounding box, waits until the
// tileset has loaded for that view and returns what was drawn and a picture.
"use strict";

const C = window.Cesium;
const state = {};

function basename(url) {
  return decodeURIComponent(String(url).split(/[?#]/)[0].split("/").pop());
}

function sleep(ms) {
  return new Promise((resolve) => setTimeout(resolve, ms));
}

// The tileset's own frame (z up) to Cesium's world frame: the root tile's
// computed transform (its `transform`, or identity: the box is then in ECEF).
function toWorldPoint(p) {
  return C.Matrix4.multiplyByPoint(state.frame, new C.Cartesian3(p[0], p[1], p[2]), new C.Cartesian3());
}
function toWorldVector(v) {
  const w = C.Matrix4.multiplyByPointAsVector(state.frame, new C.Cartesian3(v[0], v[1], v[2]), new C.Cartesian3());
  return C.Cartesian3.normalize(w, w);
}

const add = (a, b) => a.map((x, i) => x + b[i]);
const scale = (a, s) => a.map((x) => x * s);
const length = (a) => Math.hypot(a[0], a[1], a[2]);
const unit = (a) => scale(a, 1 / length(a));

// A horizontal direction in the tileset's frame at an azimuth (degrees
// clockwise from the box's +y axis, north for a perclod tileset).
function horizontal(azimuthDeg) {
  const a = (azimuthDeg * Math.PI) / 180;
  return add(scale(state.box.ux, Math.sin(a)), scale(state.box.uy, Math.cos(a)));
}

function setLight(azimuthDeg, elevationDeg) {
  const e = (elevationDeg * Math.PI) / 180;
  const towardsLight = add(scale(horizontal(azimuthDeg), Math.cos(e)), scale(state.box.uz, Math.sin(e)));
  const d = toWorldVector(scale(towardsLight, -1));
  state.scene.light = new C.DirectionalLight({ direction: d, intensity: 2.0 });
}

// Where the camera stands for a view: `distance` metres from the bounding box
// (Cesium's distance to a tile's oriented box), horizontally from the box's
// centre at `azimuth`, at the box's mid height, looking at its centre.
function cameraFor(view) {
  const b = state.box;
  const s = horizontal(view.azimuth);
  const a = (view.azimuth * Math.PI) / 180;
  const outside = (t) => Math.hypot(
    Math.max(0, Math.abs(t * Math.sin(a)) - b.hx),
    Math.max(0, Math.abs(t * Math.cos(a)) - b.hy));
  let lo = 0;
  let hi = b.hx + b.hy + view.distance + 1;
  for (let i = 0; i < 200; ++i) {
    const mid = 0.5 * (lo + hi);
    if (outside(mid) < view.distance) lo = mid;
    else hi = mid;
  }
  const t = 0.5 * (lo + hi);
  return {
    position: toWorldPoint(add(b.center, scale(s, t))),
    direction: toWorldVector(scale(s, -1)),
    up: toWorldVector(b.uz),
    centreDistance: t,
  };
}

// The drawn frame's pixels (top row first) and, if asked, the frame as PNG.
function readPixels(withPng) {
  const canvas = state.scene.canvas;
  const w = state.scene.drawingBufferWidth;
  const h = state.scene.drawingBufferHeight;
  const flipped = state.scene.context.readPixels({ x: 0, y: 0, width: w, height: h });
  const data = new Uint8Array(w * h * 4);
  for (let y = 0; y < h; ++y) data.set(flipped.subarray((h - 1 - y) * w * 4, (h - y) * w * 4), y * w * 4);
  return { w, h, data, png: withPng ? canvas.toDataURL("image/png") : null };
}

// Model pixels: those that differ from the background by more than 24 levels
// in a channel (the background is one flat colour: no sky, globe or sun).
function modelMask(px) {
  const bg = state.background;
  const n = px.w * px.h;
  const mask = new Uint8Array(n);
  const luma = new Float32Array(n);
  let count = 0;
  for (let i = 0; i < n; ++i) {
    const r = px.data[4 * i];
    const g = px.data[4 * i + 1];
    const b = px.data[4 * i + 2];
    luma[i] = 0.2126 * r + 0.7152 * g + 0.0722 * b;
    if (Math.max(Math.abs(r - bg[0]), Math.abs(g - bg[1]), Math.abs(b - bg[2])) > 24) {
      mask[i] = 1;
      ++count;
    }
  }
  return { mask, luma, count };
}

function percentile(sorted, p) {
  if (!sorted.length) return 0;
  return sorted[Math.min(sorted.length - 1, Math.floor(p * sorted.length))];
}

// Renders until the tileset has loaded everything this view needs and the
// drawn tiles have been the same for two frames; returns the drawn contents.
async function settle(timeoutMs) {
  const t0 = performance.now();
  let frames = 0;
  let last = "";
  let stable = 0;
  for (;;) {
    state.drawn.clear();
    state.widget.render();
    ++frames;
    const now = [...state.drawn].sort().join(",");
    stable = now === last ? stable + 1 : 0;
    last = now;
    if (frames >= 3 && state.tileset.tilesLoaded && stable >= 2) {
      return { drawn: [...state.drawn].sort(), frames, ms: performance.now() - t0, timedOut: false };
    }
    if (performance.now() - t0 > timeoutMs) {
      return { drawn: [...state.drawn].sort(), frames, ms: performance.now() - t0, timedOut: true };
    }
    await sleep(15);
  }
}

// The tileset's bounding box as projected this frame: the rectangle of its
// eight corners in window pixels (top row 0), or null when a corner is not
// in front of the camera.
function projectedBox(w, h) {
  const b = state.box;
  const view = state.scene.camera.viewMatrix;
  const focal = h / state.scene.camera.frustum.sseDenominator;
  const rect = { x0: Infinity, y0: Infinity, x1: -Infinity, y1: -Infinity };
  for (const sx of [-1, 1]) for (const sy of [-1, 1]) for (const sz of [-1, 1]) {
    const local = add(add(add(b.center, scale(b.ux, sx * b.hx)), scale(b.uy, sy * b.hy)), scale(b.uz, sz * b.hz));
    const eye = C.Matrix4.multiplyByPoint(view, toWorldPoint(local), new C.Cartesian3());
    if (-eye.z < 1e-3) return null;
    const x = w / 2 + (focal * eye.x) / -eye.z;
    const y = h / 2 - (focal * eye.y) / -eye.z;
    rect.x0 = Math.min(rect.x0, x);
    rect.x1 = Math.max(rect.x1, x);
    rect.y0 = Math.min(rect.y0, y);
    rect.y1 = Math.max(rect.y1, y);
  }
  return rect;
}

// Each tile from the root down: Cesium's own distance to its bounding volume
// and its screen-space error this frame (diagnostics for the report).
function tileChain() {
  const out = [];
  const frameState = state.scene.frameState;
  for (let tile = state.tileset.root; tile; tile = tile.children[0]) {
    out.push({
      content: tile.hasRenderableContent ? basename(tile._contentResource ? tile._contentResource.url : "") : null,
      geometric_error: tile.geometricError,
      cesium_distance: tile._distanceToCamera,
      sse: tile.getScreenSpaceError(frameState, false),
    });
  }
  return out;
}

window.perclodSetup = async function (o) {
  const scene0 = document.getElementById("view");
  const widget = new C.CesiumWidget(scene0, {
    globe: false,
    baseLayer: false,
    skyBox: false,
    skyAtmosphere: false,
    scene3DOnly: true,
    useDefaultRenderLoop: false,
    shadows: false,
    msaaSamples: 1,
    contextOptions: { webgl: { preserveDrawingBuffer: true, alpha: false } },
  });
  const scene = widget.scene;
  state.widget = widget;
  state.scene = scene;
  scene.fog.enabled = false;
  // A flat pale blue: no sky box or atmosphere, and far enough from any
  // grey, white or roof colour to tell the model's pixels from it.
  scene.backgroundColor = C.Color.fromBytes(184, 209, 237, 255);
  scene.screenSpaceCameraController.enableInputs = false;
  widget.clock.shouldAnimate = false;
  widget.resize();

  // The display profile's vertical field of view. Cesium's `fov` is the
  // horizontal one when the view is wider than tall.
  const fovY = (o.fovYDeg * Math.PI) / 180;
  const frustum = scene.camera.frustum;
  frustum.aspectRatio = scene.drawingBufferWidth / scene.drawingBufferHeight;
  frustum.fov = frustum.aspectRatio > 1 ? 2 * Math.atan(Math.tan(fovY / 2) * frustum.aspectRatio) : fovY;

  const tileset = await C.Cesium3DTileset.fromUrl(o.url, {
    maximumScreenSpaceError: o.maximumScreenSpaceError,
    // Nothing else may change which tile is refined: no fog-based lowering
    // of the error, no peripheral relaxation, no low-resolution first pass,
    // no skipping levels, no memory-pressure raise of the limit.
    dynamicScreenSpaceError: false,
    foveatedScreenSpaceError: false,
    progressiveResolutionHeightFraction: 0.0,
    skipLevelOfDetail: false,
    immediatelyLoadDesiredLevelOfDetail: false,
    cullRequestsWhileMoving: false,
    cacheBytes: 2 * 1024 * 1024 * 1024,
    maximumCacheOverflowBytes: 2 * 1024 * 1024 * 1024,
  });
  scene.primitives.add(tileset);
  state.tileset = tileset;
  state.drawn = new Set();
  tileset.tileVisible.addEventListener((tile) => {
    state.drawn.add(basename(tile.content.url));
  });
  if (o.forceUnlit) {
    tileset.customShader = new C.CustomShader({ lightingModel: C.LightingModel.UNLIT });
  }

  // The box in the tileset's frame (its axes: x east, y north, z up).
  const bx = o.box;
  const ux = [bx[3], bx[4], bx[5]];
  const uy = [bx[6], bx[7], bx[8]];
  const uz = [bx[9], bx[10], bx[11]];
  state.box = {
    center: [bx[0], bx[1], bx[2]],
    ux: unit(ux), uy: unit(uy), uz: unit(uz),
    hx: length(ux), hy: length(uy), hz: length(uz),
  };
  state.frame = C.Matrix4.clone(tileset.root.computedTransform);
  setLight(o.light.azimuth, o.light.elevation);

  // The background colour as drawn (tileset hidden).
  tileset.show = false;
  widget.render();
  const px = readPixels();
  state.background = [px.data[0], px.data[1], px.data[2]];
  tileset.show = true;

  const gl = scene.context._gl;
  const debug = gl.getExtension("WEBGL_debug_renderer_info");
  return {
    canvas: [scene.canvas.width, scene.canvas.height],
    drawing_buffer: [scene.drawingBufferWidth, scene.drawingBufferHeight],
    pixel_ratio: scene.frameState.pixelRatio,
    fov_y_deg: (frustum.fovy * 180) / Math.PI,
    sse_denominator: frustum.sseDenominator,
    maximum_screen_space_error: tileset.maximumScreenSpaceError,
    webgl: scene.context.webgl2 ? "WebGL 2" : "WebGL 1",
    renderer: debug ? gl.getParameter(debug.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER),
    background: state.background,
    cesium: C.VERSION,
  };
};

// view: {distance, azimuth, timeoutMs, relight: {elevation} | null}
window.perclodView = async function (view) {
  const cam = cameraFor(view);
  state.scene.camera.setView({
    destination: cam.position,
    orientation: { direction: cam.direction, up: cam.up },
  });
  const settled = await settle(view.timeoutMs);
  const cesiumDistance = Math.sqrt(
    state.tileset.root.boundingVolume.boundingVolume.distanceSquaredTo(state.scene.camera.positionWC));
  const t1 = performance.now();
  const px = readPixels(true);
  const t2 = performance.now();
  const m = modelMask(px);
  const lum = [];
  for (let i = 0; i < m.mask.length; ++i) if (m.mask[i]) lum.push(m.luma[i]);
  lum.sort((a, b) => a - b);

  // Model pixels outside the box's projection (2 px margin): content drawn
  // somewhere else than its tile says (a wrong axis or offset).
  const rect = projectedBox(px.w, px.h);
  let outside = 0;
  if (rect) {
    for (let y = 0; y < px.h; ++y) {
      for (let x = 0; x < px.w; ++x) {
        if (m.mask[y * px.w + x] && (x + 0.5 < rect.x0 - 2 || x + 0.5 > rect.x1 + 2 || y + 0.5 < rect.y0 - 2 || y + 0.5 > rect.y1 + 2)) {
          ++outside;
        }
      }
    }
  }
  // The box's face towards the camera, projected: how many pixels a model
  // filling it would cover (an upper bound for the model's coverage).
  const focal = px.h / state.scene.camera.frustum.sseDenominator;
  const b = state.box;
  const a = (view.azimuth * Math.PI) / 180;
  const faceWidth = 2 * (b.hx * Math.abs(Math.cos(a)) + b.hy * Math.abs(Math.sin(a)));
  const toFace = cam.centreDistance - (b.hx * Math.abs(Math.sin(a)) + b.hy * Math.abs(Math.cos(a)));
  const shown = (size, along) => Math.min(size * focal / Math.max(toFace, 1e-6), along);
  const boxPixels = shown(faceWidth, px.w) * shown(2 * b.hz, px.h);

  const result = {
    drawn: settled.drawn,
    frames: settled.frames,
    load_ms: Math.round(settled.ms),
    timed_out: settled.timedOut,
    cesium_distance: cesiumDistance,
    tiles: tileChain(),
    model_pixels: m.count,
    viewport_pixels: px.w * px.h,
    box_face_pixels: Math.round(boxPixels),
    box_rect: rect ? [rect.x0, rect.y0, rect.x1, rect.y1].map((v) => Math.round(v * 10) / 10) : null,
    pixels_outside_box: rect ? outside : null,
    luma_p10: percentile(lum, 0.1),
    luma_p50: percentile(lum, 0.5),
    luma_p90: percentile(lum, 0.9),
    png: px.png,
  };

  const t3 = performance.now();
  if (view.relight) {
    // The same view lit from its left and then from its right (lights level
    // with each other, square to the line of sight): a lit face turns darker
    // or brighter by how far it faces left or right, so faces of different
    // orientation change by different amounts; an unlit model does not change.
    const first = state.scene.light;
    const e = view.relight.elevation;
    setLight(view.azimuth - 90, e);
    state.widget.render();
    const left = modelMask(readPixels());
    setLight(view.azimuth + 90, e);
    state.widget.render();
    const right = modelMask(readPixels());
    state.scene.light = first;
    const delta = [];
    for (let i = 0; i < left.mask.length; ++i) {
      if (left.mask[i] && right.mask[i]) delta.push(right.luma[i] - left.luma[i]);
    }
    delta.sort((x, y) => x - y);
    result.relight = {
      pixels: delta.length,
      delta_p05: percentile(delta, 0.05),
      delta_p95: percentile(delta, 0.95),
      spread: percentile(delta, 0.95) - percentile(delta, 0.05),
    };
  }
  result.ms = { settle: Math.round(settled.ms), read: Math.round(t2 - t1), mask: Math.round(t3 - t2),
    relight: Math.round(performance.now() - t3) };
  return result;
};
