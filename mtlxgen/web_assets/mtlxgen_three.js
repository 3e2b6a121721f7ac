// mtlxgen three.js runtime: what every element module `mtlxgen three` writes shares. Each NAME.js module
// passes its shaders and manifest to createMaterial; the helpers here build geometry, the environment and the
// display pass the way `mtlxgen render` draws. Nothing here imports three: the caller passes its THREE
// namespace, so one copy of three (from npm) serves the page.
//
// Conventions (mtlxgen's shader interface, as MaterialX GenGlsl's):
// - the shaders write linear radiance; draw into a float target and encode sRGB for display (createDisplay);
// - u_envRadiance is a lat-long radiance map with a full mip chain, u_envIrradiance its irradiance (over pi),
//   both sampled with v = 0 at the image's top row; u_envMatrix rotates world directions into the map's frame;
// - texture files are read raw (NoColorSpace): the shader converts from the manifest's colorspace itself;
// - uv (0, 0) is an image's lower-left corner.

const WRAP = { periodic: "RepeatWrapping", clamp: "ClampToEdgeWrapping", mirror: "MirroredRepeatWrapping",
               constant: "ClampToEdgeWrapping" };

function flatten(v, out = []) {
  if (Array.isArray(v)) v.forEach((x) => flatten(x, out));
  else out.push(v === true ? 1 : v === false ? 0 : Number(v));
  return out;
}

function uniformValue(THREE, type, value) {
  if (value === null || value === undefined) return null;
  if (type === "mat4") return new THREE.Matrix4().fromArray(flatten(value));
  if (type === "mat3") return new THREE.Matrix3().fromArray(flatten(value));
  if (type === "vec3" && !Array.isArray(value[0])) return new THREE.Vector3().fromArray(flatten(value));
  if (Array.isArray(value)) return flatten(value);
  if (type === "bool") return value ? 1 : 0;
  return value;
}

// A uniform of a document's own struct type is an object of its members (an array of them for an array);
// anything else as uniformValue gives it.
function structValue(THREE, u) {
  if (!u.members) return uniformValue(THREE, u.type, u.value);
  const one = (v) => Object.fromEntries(u.members.map((m, i) => [m.name, uniformValue(THREE, m.type, v[i])]));
  return /\[\d+\]$/.test(u.type) ? u.value.map(one) : one(u.value);
}

// A 1x1 RGBA float texture (render's constant_texture): an image node's default colour, or transparent black.
export function constantTexture(THREE, value) {
  let v = value === null || value === undefined ? [0, 0, 0, 0] : flatten(value);
  v = { 1: [v[0], v[0], v[0], 1], 2: [v[0], v[1], 0, 1], 3: [v[0], v[1], v[2], 1] }[v.length] || v.slice(0, 4);
  const t = new THREE.DataTexture(new Float32Array(v), 1, 1, THREE.RGBAFormat, THREE.FloatType);
  t.colorSpace = THREE.NoColorSpace;
  t.needsUpdate = true;
  return t;
}

function extension(url) {
  const path = String(url).split(/[?#]/)[0];
  const dot = path.lastIndexOf(".");
  return dot < 0 ? "" : path.slice(dot + 1).toLowerCase();
}

async function hdrLoaderClass(options) {
  if (options.HDRLoader) return options.HDRLoader;
  if (options.RGBELoader) return options.RGBELoader;
  try {
    return (await import("three/addons/loaders/HDRLoader.js")).HDRLoader;
  } catch (e) {  // three before r180
    return (await import("three/addons/loaders/RGBELoader.js")).RGBELoader;
  }
}

async function exrLoaderClass(options) {
  return options.EXRLoader || (await import("three/addons/loaders/EXRLoader.js")).EXRLoader;
}

// An image's bytes exactly as stored (no premultiplication, no colour conversion), rows top first.
function imageBytes(image) {
  const canvas = typeof OffscreenCanvas !== "undefined" ? new OffscreenCanvas(1, 1) : document.createElement("canvas");
  const gl = canvas.getContext("webgl2");
  const w = image.width, h = image.height, tex = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, tex);
  gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
  gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
  gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, gl.RGBA, gl.UNSIGNED_BYTE, image);
  const fb = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, tex, 0);
  const px = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
  const lose = gl.getExtension("WEBGL_lose_context");
  if (lose) lose.loseContext();
  return px;
}

// Load one manifest texture through three's loaders: TextureLoader for PNG/JPEG/WebP, EXRLoader for .exr,
// HDRLoader (RGBELoader before r180) for .hdr. Raw colour (NoColorSpace), wrap and filter from the manifest.
// A 2-channel file (grey + alpha) becomes an RG texture (r = grey, g = alpha), as the shader reads it.
export async function loadTexture(THREE, url, entry = {}, options = {}) {
  const ext = extension(url);
  let texture;
  if (ext === "exr") {
    const Loader = await exrLoaderClass(options);
    texture = await new Loader().setDataType(options.hdrType || THREE.FloatType).loadAsync(url);
  } else if (ext === "hdr") {
    const Loader = await hdrLoaderClass(options);
    texture = await new Loader().setDataType(options.hdrType || THREE.FloatType).loadAsync(url);
  } else {
    texture = await new THREE.TextureLoader().loadAsync(url);
    if (entry.channels === 2) {
      const image = texture.image, w = image.width, h = image.height, rgba = imageBytes(image);
      const rg = new Uint8Array(w * h * 2);
      for (let y = 0; y < h; y++) {
        const src = (h - 1 - y) * w * 4, dst = y * w * 2;  // rows bottom first: uv (0, 0) is the lower left
        for (let x = 0; x < w; x++) {
          rg[dst + 2 * x] = rgba[src + 4 * x];
          rg[dst + 2 * x + 1] = rgba[src + 4 * x + 3];
        }
      }
      texture.dispose();
      texture = new THREE.DataTexture(rg, w, h, THREE.RGFormat, THREE.UnsignedByteType);
    }
  }
  texture.colorSpace = THREE.NoColorSpace;
  texture.wrapS = THREE[WRAP[entry.uaddressmode] || "RepeatWrapping"];
  texture.wrapT = THREE[WRAP[entry.vaddressmode] || "RepeatWrapping"];
  if (entry.filtertype === "closest") {
    texture.magFilter = THREE.NearestFilter;
    texture.minFilter = THREE.NearestFilter;
    texture.generateMipmaps = false;
  } else {
    texture.magFilter = THREE.LinearFilter;
    texture.minFilter = THREE.LinearMipmapLinearFilter;
    texture.generateMipmaps = true;
  }
  texture.needsUpdate = true;
  return texture;
}

// The material: a RawShaderMaterial with the element's GLSL ES 3.00 code, every public uniform at its
// manifest value, every application uniform at its default, textures loading (material.userData.ready: a
// Promise settled when they are in; a file that fails draws its default colour), and the matrices and
// camera position set per draw (onBeforeRender).
export function createMaterial(THREE, element, options = {}) {
  const { manifest } = element;
  const uniforms = {};
  for (const u of manifest.uniforms) uniforms[u.name] = { value: structValue(THREE, u) };
  for (const a of manifest.application) {
    if (a.type === "sampler2D") uniforms[a.name] = { value: constantTexture(THREE, null) };
    else if (a.default !== null && a.default !== undefined) uniforms[a.name] = { value: uniformValue(THREE, a.type, a.default) };
  }
  for (const name of ["u_worldMatrix", "u_viewProjectionMatrix", "u_worldInverseMatrix", "u_worldInverseTransposeMatrix"])
    if (!uniforms[name]) uniforms[name] = { value: new THREE.Matrix4() };
  if (!uniforms.u_viewPosition) uniforms.u_viewPosition = { value: new THREE.Vector3() };
  if (uniforms.u_envRadianceSamples) uniforms.u_envRadianceSamples.value = options.envSamples || 64;

  const loads = [];
  for (const t of manifest.textures) {
    uniforms[t.uniform] = { value: constantTexture(THREE, t["default"]) };
    const given = options.textures && options.textures[t.uniform];
    if (given && given.isTexture) { uniforms[t.uniform].value = given; continue; }
    const file = given || t.url;
    if (!file) continue;
    const url = new URL(file, element.baseUrl || (typeof document !== "undefined" ? document.baseURI : undefined)).href;
    loads.push(loadTexture(THREE, url, t, options).then(
      (texture) => { uniforms[t.uniform].value = texture; },
      (error) => { console.warn("mtlxgen: " + t.uniform + ": " + url + " did not load (" + error + "); its default colour is drawn"); }));
  }

  const strip = (source) => source.replace(/^#version[^\n]*\n/, "");
  const material = new THREE.RawShaderMaterial({
    name: manifest.element,
    vertexShader: strip(element.vertexShader),
    fragmentShader: strip(element.fragmentShader),
    uniforms,
    glslVersion: THREE.GLSL3,
    side: THREE.DoubleSide,        // render draws without culling: cut-outs show the inside
    depthFunc: THREE.LessDepth,
  });
  material.onBeforeRender = function (renderer, scene, camera, geometry, object) {
    uniforms.u_worldMatrix.value.copy(object.matrixWorld);
    uniforms.u_viewProjectionMatrix.value.multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse);
    uniforms.u_worldInverseMatrix.value.copy(object.matrixWorld).invert();
    uniforms.u_worldInverseTransposeMatrix.value.copy(uniforms.u_worldInverseMatrix.value).transpose();
    camera.getWorldPosition(uniforms.u_viewPosition.value);
  };
  material.userData.mtlxgen = { manifest };
  material.userData.ready = Promise.all(loads).then(() => material);
  if (options.environment) setEnvironment(material, options.environment, options);
  return material;
}

// Give a BufferGeometry the attribute names the shaders read, sharing three's buffers: i_position (position),
// i_normal (normal), i_tangent (tangent; computed where missing and the geometry has an index, normals and
// uv), i_bitangent (normal x tangent.xyz times tangent.w, a new buffer), i_texcoord_0 (uv), i_texcoord_1
// (uv1), i_color_0 (color).
export function prepareGeometry(THREE, geometry) {
  const a = geometry.attributes;
  if (!a.tangent && geometry.index && a.normal && a.uv) geometry.computeTangents();
  const pairs = { i_position: "position", i_normal: "normal", i_tangent: "tangent", i_texcoord_0: "uv",
                  i_texcoord_1: "uv1", i_color_0: "color" };
  for (const [ours, theirs] of Object.entries(pairs))
    if (a[theirs] && !a[ours]) geometry.setAttribute(ours, a[theirs]);
  if (a.normal && a.tangent && !a.i_bitangent) {
    const n = a.normal, t = a.tangent, b = new Float32Array(n.count * 3);
    for (let i = 0; i < n.count; i++) {
      const nx = n.getX(i), ny = n.getY(i), nz = n.getZ(i), tx = t.getX(i), ty = t.getY(i), tz = t.getZ(i);
      const w = t.itemSize > 3 ? t.getW(i) : 1;
      b[3 * i] = (ny * tz - nz * ty) * w; b[3 * i + 1] = (nz * tx - nx * tz) * w; b[3 * i + 2] = (nx * ty - ny * tx) * w;
    }
    geometry.setAttribute("i_bitangent", new THREE.BufferAttribute(b, 3));
  }
  return geometry;
}

// render's sphere (mtlxgen/render.py sphere()): radius 1, y up, u once around from +x towards -z, v from
// the bottom pole (0) to the top (1); analytic tangents along u. THREE.SphereGeometry(1, 128, 64, Math.PI)
// has the same positions and uv (its rows run top down and it has no tangents).
export function createSphere(THREE, nLon = 128, nLat = 64) {
  const count = (nLon + 1) * (nLat + 1);
  const pos = new Float32Array(count * 3), tan = new Float32Array(count * 4), uv = new Float32Array(count * 2);
  let k = 0;
  for (let j = 0; j <= nLat; j++) {
    const v = j / nLat, theta = v * Math.PI, st = Math.sin(theta), ct = Math.cos(theta);
    for (let i = 0; i <= nLon; i++, k++) {
      const u = i / nLon, phi = u * 2.0 * Math.PI;
      pos[3 * k] = st * Math.cos(phi); pos[3 * k + 1] = -ct; pos[3 * k + 2] = -st * Math.sin(phi);
      tan[4 * k] = -Math.sin(phi); tan[4 * k + 1] = 0; tan[4 * k + 2] = -Math.cos(phi); tan[4 * k + 3] = 1;
      uv[2 * k] = u; uv[2 * k + 1] = v;
    }
  }
  const index = [];
  for (let j = 0; j < nLat; j++) {
    for (let i = 0; i < nLon; i++) {
      const a = j * (nLon + 1) + i, b = a + 1, c = a + nLon + 1, d = a + nLon + 2;
      index.push(a, b, d, a, d, c);
    }
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute("position", new THREE.BufferAttribute(pos, 3));
  g.setAttribute("normal", g.attributes.position);
  g.setAttribute("tangent", new THREE.BufferAttribute(tan, 4));
  g.setAttribute("uv", new THREE.BufferAttribute(uv, 2));
  g.setIndex(index);
  return g;
}

// ------------------------------------------------------------------ environment

// One mip level down: each texel bilinearly sampled at its centre's place in the level above, clamped at the
// edges (what OpenGL's mipmap generation does on Mesa; a 2x2 box where sizes are even).
function downsample(src, w, h, c, W, H) {
  const out = new Float32Array(W * H * c);
  for (let y = 0; y < H; y++) {
    const sy = (y + 0.5) * h / H - 0.5, y0f = Math.floor(sy), fy = sy - y0f;
    const y0 = Math.min(Math.max(y0f, 0), h - 1), y1 = Math.min(Math.max(y0f + 1, 0), h - 1);
    for (let x = 0; x < W; x++) {
      const sx = (x + 0.5) * w / W - 0.5, x0f = Math.floor(sx), fx = sx - x0f;
      const x0 = Math.min(Math.max(x0f, 0), w - 1), x1 = Math.min(Math.max(x0f + 1, 0), w - 1);
      for (let ch = 0; ch < c; ch++) {
        const top = src[(y0 * w + x0) * c + ch] * (1 - fx) + src[(y0 * w + x1) * c + ch] * fx;
        const bottom = src[(y1 * w + x0) * c + ch] * (1 - fx) + src[(y1 * w + x1) * c + ch] * fx;
        out[(y * W + x) * c + ch] = top * (1 - fy) + bottom * fy;
      }
    }
  }
  return out;
}

export function mipChain(data, width, height, channels) {
  const levels = [{ data, width, height }];
  while (width > 1 || height > 1) {
    const W = Math.max(1, width >> 1), H = Math.max(1, height >> 1);
    data = downsample(data, width, height, channels, W, H);
    levels.push({ data, width: W, height: H });
    width = W; height = H;
  }
  return levels;
}

function sh9(x, y, z) {
  return [0.282095, 0.488603 * y, 0.488603 * z, 0.488603 * x, 1.092548 * x * y, 1.092548 * y * z,
          0.315392 * (3 * z * z - 1), 1.092548 * x * z, 0.546274 * (x * x - y * y)];
}

function latlongDirection(u, v) {
  const el = (0.5 - v) * Math.PI, az = (u - 0.5) * 2.0 * Math.PI;
  return [Math.cos(el) * Math.sin(az), Math.sin(el), -Math.cos(el) * Math.cos(az), Math.cos(el)];
}

// Irradiance E(n)/pi of a lat-long map (RGBA rows top first) from its order-2 spherical harmonics
// (Ramamoorthi & Hanrahan 2001), as render's irradiance_map computes it.
export function irradianceMap(data, width, height, outWidth = 128, outHeight = 64) {
  const coeffs = new Float64Array(27), dA = (Math.PI / height) * (2.0 * Math.PI / width);
  for (let y = 0; y < height; y++) {
    for (let x = 0; x < width; x++) {
      const d = latlongDirection((x + 0.5) / width, (y + 0.5) / height), sa = d[3] * dA, b = sh9(d[0], d[1], d[2]);
      const p = (y * width + x) * 4;
      for (let k = 0; k < 9; k++)
        for (let c = 0; c < 3; c++) coeffs[3 * k + c] += b[k] * data[p + c] * sa;
    }
  }
  const band = [Math.PI, 2 * Math.PI / 3, 2 * Math.PI / 3, 2 * Math.PI / 3, Math.PI / 4, Math.PI / 4, Math.PI / 4,
                Math.PI / 4, Math.PI / 4];
  const out = new Float32Array(outWidth * outHeight * 4);
  for (let y = 0; y < outHeight; y++) {
    for (let x = 0; x < outWidth; x++) {
      const d = latlongDirection((x + 0.5) / outWidth, (y + 0.5) / outHeight), b = sh9(d[0], d[1], d[2]);
      for (let c = 0; c < 3; c++) {
        let s = 0;
        for (let k = 0; k < 9; k++) s += b[k] * coeffs[3 * k + c] * band[k];
        out[(y * outWidth + x) * 4 + c] = Math.max(s / Math.PI, 0);
      }
      out[(y * outWidth + x) * 4 + 3] = 1;
    }
  }
  return out;
}

// The environment render lights with, from a lat-long texture three loaded (EXRLoader, HDRLoader: float or
// half float RGBA data; or {data, width, height} RGBA floats, rows top first): the radiance with a full mip
// chain, its SH irradiance, the mip count. options.type: THREE.FloatType (default; linear filtering needs
// OES_texture_float_linear) or THREE.HalfFloatType.
export function createEnvironment(THREE, source, options = {}) {
  let { data, width, height } = source.isTexture ? source.image : source;
  if (data instanceof Uint16Array) data = Float32Array.from(data, (h) => THREE.DataUtils.fromHalfFloat(h));
  const channels = Math.round(data.length / (width * height));
  let rgba = new Float32Array(width * height * 4);
  for (let i = 0; i < width * height; i++) {
    for (let c = 0; c < 3; c++) rgba[4 * i + c] = data[channels * i + Math.min(c, channels - 1)];
    rgba[4 * i + 3] = 1;
  }
  // rows top first: a texture three flips on upload (flipY) holds them so; one it does not holds them bottom first
  if (source.isTexture && !source.flipY) {
    const flipped = new Float32Array(rgba.length), row = width * 4;
    for (let y = 0; y < height; y++) flipped.set(rgba.subarray((height - 1 - y) * row, (height - y) * row), y * row);
    rgba = flipped;
  }
  const type = options.type || THREE.FloatType;
  const store = (a) => (type === THREE.HalfFloatType ? Uint16Array.from(a, (f) => THREE.DataUtils.toHalfFloat(f)) : a);
  const levels = mipChain(rgba, width, height, 4);
  const radiance = new THREE.DataTexture(store(rgba), width, height, THREE.RGBAFormat, type);
  radiance.mipmaps = levels.map((l) => ({ data: store(l.data), width: l.width, height: l.height }));
  radiance.generateMipmaps = false;
  radiance.minFilter = THREE.LinearMipmapLinearFilter;
  radiance.magFilter = THREE.LinearFilter;
  radiance.wrapS = radiance.wrapT = THREE.RepeatWrapping;
  radiance.flipY = false;
  radiance.colorSpace = THREE.NoColorSpace;
  radiance.needsUpdate = true;
  const irradiance = new THREE.DataTexture(store(irradianceMap(rgba, width, height)), 128, 64, THREE.RGBAFormat, type);
  irradiance.minFilter = irradiance.magFilter = THREE.LinearFilter;
  irradiance.wrapS = irradiance.wrapT = THREE.RepeatWrapping;
  irradiance.flipY = false;
  irradiance.colorSpace = THREE.NoColorSpace;
  irradiance.needsUpdate = true;
  return { radiance, irradiance, mips: Math.floor(Math.log2(Math.max(width, height))) + 1 };
}

// The environment with its radiance GGX-prefiltered per mip level, for materials of the prefiltered method
// (manifest "environment": "prefiltered"; the recipe is the manifest's u_envRadiance "prefilter", carried out as
// render's environment.Prefilter does): each level drawn by the prefilter shaders (a module's `prefilter`:
// {vertex, fragment, samples}, GLSL ES 3.00) from the box chain into a float target of the level's size, read
// back into the new texture's level (linear-mipmap-linear, repeat in u, clamp to edge in v). Without
// EXT_color_buffer_float the environment comes back as it is (the box chain) with a console warning.
export function prefilterEnvironment(THREE, renderer, environment, prefilter) {
  if (!renderer.extensions.has("EXT_color_buffer_float")) {
    console.warn("mtlxgen: no EXT_color_buffer_float: the environment is box-filtered, not GGX-prefiltered");
    return environment;
  }
  const radiance = environment.radiance, width = radiance.image.width, height = radiance.image.height;
  const sizes = [[width, height]];
  while (sizes[sizes.length - 1][0] > 1 || sizes[sizes.length - 1][1] > 1) {
    const [w, h] = sizes[sizes.length - 1];
    sizes.push([Math.max(1, w >> 1), Math.max(1, h >> 1)]);
  }
  const source = radiance.clone();          // read clamped in v, as render's pass reads it (the poles never blend)
  source.wrapT = THREE.ClampToEdgeWrapping;
  source.needsUpdate = true;
  const strip = (text) => text.replace(/^#version[^\n]*\n/, "");
  const material = new THREE.RawShaderMaterial({
    glslVersion: THREE.GLSL3, vertexShader: strip(prefilter.vertex), fragmentShader: strip(prefilter.fragment),
    uniforms: { u_source: { value: source }, u_sourceMips: { value: sizes.length }, u_level: { value: 0 },
                u_samples: { value: prefilter.samples } },
    depthTest: false, depthWrite: false,
  });
  const triangle = new THREE.BufferGeometry();        // three vertices; the shader places them by gl_VertexID
  triangle.setAttribute("position", new THREE.BufferAttribute(new Float32Array(9), 3));
  const mesh = new THREE.Mesh(triangle, material);
  mesh.frustumCulled = false;
  const scene = new THREE.Scene();
  scene.add(mesh);
  const camera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
  const previous = renderer.getRenderTarget();
  const half = radiance.type === THREE.HalfFloatType;
  const levels = [];
  for (let level = 0; level < sizes.length; level++) {
    const [w, h] = sizes[level];
    const target = new THREE.WebGLRenderTarget(w, h, {
      type: THREE.FloatType, format: THREE.RGBAFormat, depthBuffer: false, stencilBuffer: false,
      minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter, generateMipmaps: false,
    });
    material.uniforms.u_level.value = level;
    renderer.setRenderTarget(target);
    renderer.render(scene, camera);
    const pixels = new Float32Array(w * h * 4);      // rows as the level's: row 0 is v = 0, the map's top
    renderer.readRenderTargetPixels(target, 0, 0, w, h, pixels);
    target.dispose();
    levels.push({ data: half ? Uint16Array.from(pixels, (f) => THREE.DataUtils.toHalfFloat(f)) : pixels,
                  width: w, height: h });
  }
  renderer.setRenderTarget(previous);
  triangle.dispose();
  material.dispose();
  source.dispose();
  const out = new THREE.DataTexture(levels[0].data, width, height, THREE.RGBAFormat, radiance.type);
  out.mipmaps = levels;
  out.generateMipmaps = false;
  out.minFilter = THREE.LinearMipmapLinearFilter;
  out.magFilter = THREE.LinearFilter;
  out.wrapS = THREE.RepeatWrapping;
  out.wrapT = THREE.ClampToEdgeWrapping;
  out.flipY = false;
  out.colorSpace = THREE.NoColorSpace;
  out.needsUpdate = true;
  return { ...environment, radiance: out, prefiltered: true };
}

// Bind an environment (createEnvironment's) to a material: u_envRadiance, u_envIrradiance,
// u_envRadianceMips; options.envSamples (u_envRadianceSamples, default 64 as render), options.envIntensity
// (u_envLightIntensity, default 1), options.envMatrix (u_envMatrix, a THREE.Matrix4; default diag(-1, 1, -1, 1)).
export function setEnvironment(material, environment, options = {}) {
  const u = material.uniforms;
  const set = (name, value) => { if (u[name]) u[name].value = value; };
  set("u_envRadiance", environment.radiance);
  set("u_envIrradiance", environment.irradiance);
  set("u_envRadianceMips", environment.mips);
  if (options.envSamples) set("u_envRadianceSamples", options.envSamples);
  if (options.envIntensity !== undefined) set("u_envLightIntensity", options.envIntensity);
  if (options.envMatrix && u.u_envMatrix) u.u_envMatrix.value.copy(options.envMatrix);
  return material;
}

// ------------------------------------------------------------------ display

// Draw a scene as render does: linear radiance into a float target cleared to transparent black, then an
// encode pass writes sRGB 8-bit (alpha as is) into the renderer's canvas.
export function createDisplay(THREE, renderer, width, height) {
  const target = new THREE.WebGLRenderTarget(width, height, {
    type: THREE.FloatType, format: THREE.RGBAFormat, depthBuffer: true, stencilBuffer: false,
    minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter, generateMipmaps: false,
  });
  const encode = new THREE.RawShaderMaterial({
    glslVersion: THREE.GLSL3,
    uniforms: { u_image: { value: target.texture } },
    vertexShader: "in vec3 position;\nvoid main() { gl_Position = vec4(position.xy, 0.0, 1.0); }\n",
    fragmentShader: "precision highp float;\nuniform highp sampler2D u_image;\nout vec4 o_color;\n" +
      "vec3 encode(vec3 c) {\n  c = max(c, 0.0);\n" +
      "  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, vec3(greaterThan(c, vec3(0.0031308))));\n}\n" +
      "void main() {\n  vec4 v = texelFetch(u_image, ivec2(gl_FragCoord.xy), 0);\n" +
      "  o_color = clamp(vec4(encode(v.rgb), v.a), 0.0, 1.0);\n}\n",
    depthTest: false, depthWrite: false,
  });
  const quad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), encode);
  quad.frustumCulled = false;
  const quadScene = new THREE.Scene();
  quadScene.add(quad);
  const quadCamera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
  return {
    target,
    render(scene, camera) {
      const clear = new THREE.Color(), alpha = renderer.getClearAlpha();
      renderer.getClearColor(clear);
      renderer.setRenderTarget(target);
      renderer.setClearColor(0x000000, 0);
      renderer.clear(true, true, true);
      renderer.render(scene, camera);
      renderer.setRenderTarget(null);
      renderer.render(quadScene, quadCamera);
      renderer.setClearColor(clear, alpha);
    },
    dispose() { target.dispose(); encode.dispose(); quad.geometry.dispose(); },
  };
}
