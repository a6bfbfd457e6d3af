// The separable method of `sss render` on WebGPU, in the browser: the same WGSL, the same buffers
// (written by `sss view` from the renderer's own uniform blocks: frames/SCENE/frame.json and its
// .bin files) and the same passes in the same order (gpu::Renderer): shadow maps, the scene pass,
// unpacking, the kernel's 1D passes, recombination. The light follows the mouse; the method
// switches between the material's table variants (frames/methods.bin).

const query = new URLSearchParams(location.search);
const capture = query.has("capture");
const status = document.getElementById("status");

function fail(message) {
  status.textContent = message;
  if (capture) {
    const json = JSON.stringify({ error: message });
    document.getElementById("capture").textContent = json;
    if (query.has("post")) fetch(query.get("post"), { method: "POST", body: json });
  }
  throw new Error(message);
}

async function fetchJson(path) {
  const r = await fetch(path);
  if (!r.ok) fail(`cannot read ${path}: ${r.status}`);
  return r.json();
}

async function fetchBytes(path) {
  const r = await fetch(path);
  if (!r.ok) fail(`cannot read ${path}: ${r.status}`);
  return new Uint8Array(await r.arrayBuffer());
}

// Column-major 4×4 matrices as glam writes them (right-handed, depth 0 to 1).
function mul(a, b) {
  const out = new Float64Array(16);
  for (let c = 0; c < 4; c++) {
    for (let r = 0; r < 4; r++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
      out[c * 4 + r] = s;
    }
  }
  return out;
}

const sub3 = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot3 = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross3 = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const norm3 = (a) => { const l = Math.hypot(a[0], a[1], a[2]); return [a[0] / l, a[1] / l, a[2] / l]; };

function lookAt(eye, centre, up) {
  const f = norm3(sub3(centre, eye));
  const s = norm3(cross3(f, up));
  const u = cross3(s, f);
  return [s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
    -dot3(eye, s), -dot3(eye, u), dot3(eye, f), 1];
}

function orthographic(l, r, b, t, near, far) {
  const w = 1 / (r - l), h = 1 / (t - b), d = 1 / (near - far);
  return [2 * w, 0, 0, 0, 0, 2 * h, 0, 0, 0, 0, d, 0, -(l + r) * w, -(t + b) * h, d * near, 1];
}

function inverse(m) {
  const inv = new Float64Array(16);
  const a = Array.from(m);
  // Gauss–Jordan on [A | I], column-major storage read as rows of the transpose.
  const n = 4, aug = [];
  for (let r = 0; r < n; r++) {
    aug.push([]);
    for (let c = 0; c < n; c++) aug[r].push(a[c * 4 + r]);
    for (let c = 0; c < n; c++) aug[r].push(r === c ? 1 : 0);
  }
  for (let c = 0; c < n; c++) {
    let p = c;
    for (let r = c + 1; r < n; r++) if (Math.abs(aug[r][c]) > Math.abs(aug[p][c])) p = r;
    [aug[c], aug[p]] = [aug[p], aug[c]];
    const d = aug[c][c];
    for (let k = 0; k < 2 * n; k++) aug[c][k] /= d;
    for (let r = 0; r < n; r++) {
      if (r === c) continue;
      const f = aug[r][c];
      for (let k = 0; k < 2 * n; k++) aug[r][k] -= f * aug[c][k];
    }
  }
  for (let r = 0; r < n; r++) for (let c = 0; c < n; c++) inv[c * 4 + r] = aug[r][n + c];
  return inv;
}

// A directional light's shadow projection, as gpu::Scene::light_view_proj makes it.
function directionalViewProj(frame, towards) {
  const c = frame.shadow_centre, r = frame.shadow_radius;
  const eye = [c[0] + towards[0] * 3 * r, c[1] + towards[1] * 3 * r, c[2] + towards[2] * 3 * r];
  const up = Math.abs(norm3(towards)[1]) > 0.99 ? [0, 0, 1] : [0, 1, 0];
  return mul(orthographic(-r, r, -r, r, 0.1, 6 * r), lookAt(eye, c, up));
}

function toBase64(bytes) {
  let s = "";
  for (let i = 0; i < bytes.length; i += 0x8000) {
    s += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
  }
  return btoa(s);
}

class Frame {
  constructor(device, frame, bins) {
    this.device = device;
    this.frame = frame;
    const d = device, f = frame;
    const n = f.width * f.height;
    const U = GPUBufferUsage;
    const buffer = (bytes, usage) => {
      const b = d.createBuffer({ size: Math.max(16, bytes.byteLength), usage: usage | U.COPY_DST });
      d.queue.writeBuffer(b, 0, bytes);
      return b;
    };
    const pixels = (count) => d.createBuffer({ size: count * 16, usage: U.STORAGE | U.COPY_SRC | U.COPY_DST });
    this.globalsBytes = bins["globals.bin"].slice();
    this.globals = buffer(this.globalsBytes, U.UNIFORM);
    this.vertices = buffer(bins["vertices.bin"], U.VERTEX);
    this.indices = buffer(bins["indices.bin"], U.INDEX);
    this.shadowUniforms = f.shadows.map((s) => buffer(new Float32Array(s.view_proj), U.UNIFORM));
    for (const name of ["diffuse", "specular", "geometry", "albedo", "scattered", "tmp", "linear"]) {
      this[name] = pixels(n);
    }
    this.display = pixels(Math.ceil(n / 4));
    this.blurUniforms = f.blur.map((_, i) => buffer(bins[`blur_${i}.bin`], U.UNIFORM));
    this.taps = {};
    for (const s of f.blur) {
      const key = `${s.material}_${s.pass}`;
      if (!this.taps[key]) {
        this.taps[key] = [buffer(bins[`taps_${key}.bin`], U.STORAGE), buffer(bins[`cells_${key}.bin`], U.STORAGE)];
      }
    }
    this.combineUniform = buffer(bins["combine.bin"], U.UNIFORM);
    const layers = Math.max(1, f.shadows.length);
    this.shadowMaps = d.createTexture({
      size: [f.shadow_size, f.shadow_size, layers], format: "depth32float",
      usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.TEXTURE_BINDING,
    });
    const target = (format) => d.createTexture({
      size: [f.width, f.height], format,
      usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.TEXTURE_BINDING,
    });
    this.targets = ["rgba32float", "rgba16float", "rg32float"].map(target);
    this.depth = target("depth32float");
    this.sampler = d.createSampler({ compare: "less-equal", magFilter: "linear", minFilter: "linear" });
    const vertexLayout = {
      arrayStride: 56,
      attributes: [
        { shaderLocation: 0, offset: 0, format: "float32x3" },
        { shaderLocation: 1, offset: 12, format: "float32x3" },
        { shaderLocation: 2, offset: 24, format: "float32x3" },
        { shaderLocation: 3, offset: 36, format: "float32" },
        { shaderLocation: 4, offset: 40, format: "uint32" },
        { shaderLocation: 5, offset: 44, format: "float32x3" },
      ],
    };
    const depthStencil = { format: "depth32float", depthWriteEnabled: true, depthCompare: "less" };
    const module = (code) => d.createShaderModule({ code });
    const shadowModule = module(f.wgsl.shadow);
    this.shadowPipeline = d.createRenderPipeline({
      layout: "auto", vertex: { module: shadowModule, entryPoint: "vs", buffers: [vertexLayout] }, depthStencil,
    });
    const sceneModule = module(f.wgsl.scene);
    this.scenePipeline = d.createRenderPipeline({
      layout: "auto",
      vertex: { module: sceneModule, entryPoint: "vs", buffers: [vertexLayout] },
      fragment: { module: sceneModule, entryPoint: "fs", targets: ["rgba32float", "rgba16float", "rg32float"].map((format) => ({ format })) },
      depthStencil,
    });
    const compute = (code) => d.createComputePipeline({ layout: "auto", compute: { module: module(code), entryPoint: "main" } });
    this.unpackPipeline = compute(f.wgsl.unpack);
    this.blurPipeline = compute(f.wgsl.blur);
    this.combinePipeline = compute(f.wgsl.combine);
  }

  // The materials' tables (method variant) and the first light's direction (null: as written).
  update(materialBytes, towards) {
    const f = this.frame;
    if (materialBytes) this.globalsBytes.set(materialBytes, f.materials_offset);
    if (towards && f.shadows.length > 0 && f.shadows[0].directional) {
      const t = norm3(towards);
      const vp = directionalViewProj(f, t);
      const floats = new Float32Array(this.globalsBytes.buffer, this.globalsBytes.byteOffset + f.lights_offset, 48);
      floats.set(Float32Array.from(vp), 0);
      floats.set(Float32Array.from(inverse(vp)), 16);
      floats.set([t[0], t[1], t[2], 0], 32);
      this.device.queue.writeBuffer(this.shadowUniforms[0], 0, Float32Array.from(vp));
    }
    this.device.queue.writeBuffer(this.globals, 0, this.globalsBytes);
  }

  encode() {
    const d = this.device, f = this.frame;
    const enc = d.createCommandEncoder();
    const bind = (pipeline, resources) => d.createBindGroup({
      layout: pipeline.getBindGroupLayout(0),
      entries: resources.map((r, binding) => ({ binding, resource: r instanceof GPUBuffer ? { buffer: r } : r })),
    });
    f.shadows.forEach((s, i) => {
      const view = this.shadowMaps.createView({ dimension: "2d", baseArrayLayer: i, arrayLayerCount: 1 });
      const pass = enc.beginRenderPass({
        colorAttachments: [],
        depthStencilAttachment: { view, depthClearValue: 1, depthLoadOp: "clear", depthStoreOp: "store" },
      });
      if (s.shadow) {
        pass.setPipeline(this.shadowPipeline);
        pass.setBindGroup(0, bind(this.shadowPipeline, [this.shadowUniforms[i]]));
        pass.setVertexBuffer(0, this.vertices);
        pass.setIndexBuffer(this.indices, "uint32");
        pass.drawIndexed(f.index_count);
      }
      pass.end();
    });
    const clears = [[0, 0, 0, 0], [0, 0, 0, 0], [f.far, 0, 0, 0]];
    const scene = enc.beginRenderPass({
      colorAttachments: this.targets.map((t, i) => ({
        view: t.createView(), clearValue: clears[i], loadOp: "clear", storeOp: "store",
      })),
      depthStencilAttachment: { view: this.depth.createView(), depthClearValue: 1, depthLoadOp: "clear", depthStoreOp: "store" },
    });
    scene.setPipeline(this.scenePipeline);
    scene.setBindGroup(0, bind(this.scenePipeline, [
      this.globals, this.shadowMaps.createView({ dimension: "2d-array" }), this.sampler,
    ]));
    scene.setVertexBuffer(0, this.vertices);
    scene.setIndexBuffer(this.indices, "uint32");
    scene.drawIndexed(f.index_count);
    scene.end();
    const groups = [Math.ceil(f.width / 8), Math.ceil(f.height / 8)];
    const dispatch = (pipeline, resources) => {
      const pass = enc.beginComputePass();
      pass.setPipeline(pipeline);
      pass.setBindGroup(0, bind(pipeline, resources));
      pass.dispatchWorkgroups(groups[0], groups[1]);
      pass.end();
    };
    dispatch(this.unpackPipeline, [
      ...this.targets.map((t) => t.createView()), this.diffuse, this.specular, this.geometry, this.albedo,
    ]);
    enc.clearBuffer(this.scattered);
    f.blur.forEach((s, i) => {
      const [taps, cells] = this.taps[`${s.material}_${s.pass}`];
      const [from, to] = s.horizontal ? [this.diffuse, this.tmp] : [this.tmp, this.scattered];
      dispatch(this.blurPipeline, [this.blurUniforms[i], taps, from, this.geometry, to, cells]);
    });
    dispatch(this.combinePipeline, [
      this.combineUniform, this.scattered, this.specular, this.albedo, this.linear, this.display,
      this.diffuse, this.geometry,
    ]);
    return enc;
  }

  async draw(canvas) {
    const d = this.device, f = this.frame, n = f.width * f.height;
    const enc = this.encode();
    const read = (src, size) => {
      const b = d.createBuffer({ size, usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST });
      enc.copyBufferToBuffer(src, 0, b, 0, size);
      return b;
    };
    const linear = read(this.linear, n * 16);
    const display = read(this.display, Math.ceil(n / 4) * 16);
    d.queue.submit([enc.finish()]);
    await Promise.all([linear.mapAsync(GPUMapMode.READ), display.mapAsync(GPUMapMode.READ)]);
    const rgba = new Uint8ClampedArray(display.getMappedRange().slice(0, n * 4));
    canvas.width = f.width;
    canvas.height = f.height;
    canvas.getContext("2d").putImageData(new ImageData(rgba, f.width, f.height), 0, 0);
    const pixels = new Float32Array(linear.getMappedRange().slice(0));
    linear.unmap();
    display.unmap();
    return pixels;
  }
}

async function main() {
  if (!navigator.gpu) fail("this browser has no WebGPU (navigator.gpu is missing)");
  const adapter = await navigator.gpu.requestAdapter();
  if (!adapter) fail("no WebGPU adapter");
  const device = await adapter.requestDevice({
    requiredLimits: { maxStorageBuffersPerShaderStage: 8 },
  });
  device.addEventListener("uncapturederror", (e) => fail(`WebGPU: ${e.error.message}`));
  const site = await fetchJson("site.json");
  const names = site.scenes.map((s) => s.name);
  const sceneName = query.get("scene") || site.default_scene;
  if (!names.includes(sceneName)) fail(`no scene ${sceneName} here: ${names.join(", ")}`);
  document.getElementById("title").textContent = `${site.material} on WebGPU`;
  const select = document.getElementById("scene");
  for (const name of names) select.add(new Option(name, name, false, name === sceneName));
  select.onchange = () => { query.set("scene", select.value); location.search = query.toString(); };
  const base = `frames/${sceneName}`;
  const frame = await fetchJson(`${base}/frame.json`);
  const bins = {};
  for (const name of frame.files) bins[name] = await fetchBytes(`${base}/${name}`);
  const methods = await fetchBytes("frames/methods.bin");
  const variant = (k) => methods.subarray(k * site.material_bytes, (k + 1) * site.material_bytes);
  const scene = site.scenes.find((s) => s.name === sceneName);
  if (scene.reference) {
    document.getElementById("reference").src = scene.reference;
    document.getElementById("reference-figure").hidden = false;
  }
  const canvas = document.getElementById("canvas");
  const view = new Frame(device, frame, bins);
  const method = document.getElementById("method");
  let towards = null, busy = false, again = false;
  const redraw = async () => {
    if (busy) { again = true; return; }
    busy = true;
    do {
      again = false;
      view.update(variant(Number(method.value)), towards);
      await view.draw(canvas);
    } while (again);
    busy = false;
    status.textContent = "";
    document.body.dataset.drawn = "1";
  };
  if (capture) {
    view.update(variant(3), null);
    const linear = await view.draw(canvas);
    const rgb = new Float32Array(frame.width * frame.height * 3);
    for (let i = 0; i < frame.width * frame.height; i++) {
      rgb[3 * i] = linear[4 * i];
      rgb[3 * i + 1] = linear[4 * i + 1];
      rgb[3 * i + 2] = linear[4 * i + 2];
    }
    // The light the mouse moves, recomputed here as gpu::Scene::light_view_proj does, against
    // the renderer's own matrices for the default light (the harness checks the difference).
    let lightError = null;
    if (frame.shadows.length > 0 && frame.shadows[0].directional) {
      const lights = new Float32Array(bins["globals.bin"].buffer.slice(frame.lights_offset, frame.lights_offset + 192));
      const vp = directionalViewProj(frame, Array.from(lights.subarray(32, 35)));
      const inv = inverse(vp);
      lightError = 0;
      for (let k = 0; k < 16; k++) {
        lightError = Math.max(lightError, Math.abs(vp[k] - lights[k]) / (1 + Math.abs(lights[k])),
          Math.abs(inv[k] - lights[16 + k]) / (1 + Math.abs(lights[16 + k])));
      }
    }
    const info = adapter.info || {};
    const json = JSON.stringify({
      width: frame.width, height: frame.height, rgb: toBase64(new Uint8Array(rgb.buffer)),
      adapter: [info.vendor, info.architecture, info.device, info.description].filter((x) => x).join(" "),
      light_error: lightError,
    });
    document.getElementById("capture").textContent = json;
    status.textContent = "captured";
    // ?post=URL: also send it there (a headless browser's harness reads it so).
    if (query.has("post")) await fetch(query.get("post"), { method: "POST", body: json });
    return;
  }
  method.onchange = redraw;
  canvas.onmousemove = (e) => {
    const r = canvas.getBoundingClientRect();
    const az = ((e.clientX - r.left) / r.width - 0.5) * 2 * Math.PI;
    const el = Math.max(0.05, (1 - (e.clientY - r.top) / r.height) * Math.PI / 2);
    towards = [Math.sin(az) * Math.cos(el), Math.sin(el), Math.cos(az) * Math.cos(el)];
    redraw();
  };
  await redraw();
}

main().catch((e) => fail(String(e && e.message ? e.message : e)));
