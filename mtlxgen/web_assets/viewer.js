// mtlxgen web viewer: draws one element's GLSL ES 3.00 shaders on render's sphere in WebGL2, as
// `mtlxgen render` draws them (mtlxgen/web.py writes the data block this reads). Linear radiance goes into a
// float framebuffer, then an encode pass writes sRGB 8-bit (alpha as is) into the canvas.
// window.mtlxgen: {ready, error, frames, draw(), pixels() -> base64 RGBA8 rows top first, camera}.
(function () {
  "use strict";
  var state = { ready: false, error: null, frames: 0 };
  window.mtlxgen = state;
  var statusLine = document.getElementById("status");

  function fail(message) {
    state.error = message;
    statusLine.textContent = message;
    statusLine.className = "error";
    if (window.console) console.error(message);
  }

  function bytes(b64) {
    var bin = atob(b64), out = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) out[i] = bin.charCodeAt(i);
    return out.buffer;
  }

  var data;
  try {
    data = JSON.parse(document.getElementById("mtlxgen-data").textContent);
  } catch (e) {
    fail("mtlxgen: the page's data does not read: " + e);
    return;
  }
  var canvas = document.getElementById("view");
  var gl = canvas.getContext("webgl2", { alpha: true, premultipliedAlpha: false, antialias: false, depth: false,
                                         stencil: false, preserveDrawingBuffer: true });
  if (!gl) { fail("mtlxgen: this browser has no WebGL2"); return; }
  if (!gl.getExtension("EXT_color_buffer_float")) {
    fail("mtlxgen: WebGL2 without EXT_color_buffer_float: no float framebuffer to draw radiance into");
    return;
  }
  var floatLinear = !!gl.getExtension("OES_texture_float_linear");

  // ------------------------------------------------------------ programs
  function compile(type, source, what) {
    var s = gl.createShader(type);
    gl.shaderSource(s, source);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS))
      throw new Error(what + " does not compile:\n" + gl.getShaderInfoLog(s));
    return s;
  }
  function link(vertex, fragment, what) {
    var p = gl.createProgram();
    gl.attachShader(p, compile(gl.VERTEX_SHADER, vertex, what + " vertex stage"));
    gl.attachShader(p, compile(gl.FRAGMENT_SHADER, fragment, what + " fragment stage"));
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS))
      throw new Error(what + " does not link:\n" + gl.getProgramInfoLog(p));
    return p;
  }

  var ENCODE_VS = "#version 300 es\nvoid main() {\n" +
    "  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);\n" +
    "  gl_Position = vec4(p, 0.0, 1.0);\n}\n";
  // images.to_srgb8: clamp below at 0, the sRGB curve, clamp to 1; the 8-bit store rounds
  var ENCODE_FS = "#version 300 es\nprecision highp float;\nuniform highp sampler2D u_image;\n" +
    "out vec4 o_color;\n" +
    "vec3 encode(vec3 c) {\n  c = max(c, 0.0);\n" +
    "  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, vec3(greaterThan(c, vec3(0.0031308))));\n}\n" +
    "void main() {\n  vec4 v = texelFetch(u_image, ivec2(gl_FragCoord.xy), 0);\n" +
    "  o_color = clamp(vec4(encode(v.rgb), v.a), 0.0, 1.0);\n}\n";

  // ------------------------------------------------------------ textures
  var FORMATS = {  // [channels][type] -> [internal format, format]
    1: { f16: [gl.R16F, gl.RED], f32: [gl.R32F, gl.RED] },
    2: { f16: [gl.RG16F, gl.RG], f32: [gl.RG32F, gl.RG] },
    3: { f16: [gl.RGB16F, gl.RGB], f32: [gl.RGB32F, gl.RGB] },
    4: { f16: [gl.RGBA16F, gl.RGBA], f32: [gl.RGBA32F, gl.RGBA] }
  };
  function makeTexture(img, repeat) {
    var t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, t);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
    var f32 = img.type === "f32";
    // 32-bit floats filter linearly only with OES_texture_float_linear: else the same values as 16-bit floats
    var internal = FORMATS[img.channels][f32 && floatLinear ? "f32" : "f16"][0];
    var format = FORMATS[img.channels].f32[1];
    var w = img.width, h = img.height;
    for (var level = 0; level < img.levels.length; level++) {
      var buf = bytes(img.levels[level]);
      var pixels = f32 ? new Float32Array(buf) : new Uint16Array(buf);
      gl.texImage2D(gl.TEXTURE_2D, level, internal, w, h, 0, format, f32 ? gl.FLOAT : gl.HALF_FLOAT, pixels);
      w = Math.max(1, w >> 1); h = Math.max(1, h >> 1);
    }
    var mips = img.mipmaps && img.levels.length > 1;
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_BASE_LEVEL, 0);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAX_LEVEL, img.levels.length - 1);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, mips ? gl.LINEAR_MIPMAP_LINEAR : gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    var wrap = repeat === false ? gl.CLAMP_TO_EDGE : gl.REPEAT;
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, wrap);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, wrap);
    return t;
  }

  // ------------------------------------------------------------ uniforms
  var SETTERS = {
    "float": function (l, v) { gl.uniform1fv(l, flat(v)); },
    "int": function (l, v) { gl.uniform1iv(l, ints(v)); },
    "bool": function (l, v) { gl.uniform1iv(l, ints(v)); },
    "vec2": function (l, v) { gl.uniform2fv(l, flat(v)); },
    "vec3": function (l, v) { gl.uniform3fv(l, flat(v)); },
    "vec4": function (l, v) { gl.uniform4fv(l, flat(v)); },
    "ivec2": function (l, v) { gl.uniform2iv(l, ints(v)); },
    "ivec3": function (l, v) { gl.uniform3iv(l, ints(v)); },
    "ivec4": function (l, v) { gl.uniform4iv(l, ints(v)); },
    "mat2": function (l, v) { gl.uniformMatrix2fv(l, false, flat(v)); },
    "mat3": function (l, v) { gl.uniformMatrix3fv(l, false, flat(v)); },
    "mat4": function (l, v) { gl.uniformMatrix4fv(l, false, flat(v)); }
  };
  function flatten(v, out) {
    if (Array.isArray(v)) { for (var i = 0; i < v.length; i++) flatten(v[i], out); }
    else out.push(v === true ? 1 : v === false ? 0 : Number(v));
    return out;
  }
  function flat(v) { return new Float32Array(flatten(v, [])); }
  function ints(v) { return new Int32Array(flatten(v, []).map(function (x) { return Math.trunc(x); })); }

  // struct declarations of a stage: name -> [[member type, member name], ...] in declaration order
  function structs(source) {
    var out = {}, re = /struct\s+(\w+)\s*\{([^}]*)\}/g, m;
    while ((m = re.exec(source))) {
      out[m[1]] = m[2].split(";").map(function (s) { return s.trim().split(/\s+/); })
        .filter(function (p) { return p.length === 2; });
    }
    return out;
  }

  function setUniform(prog, known, name, type, value) {
    if (value === null || value === undefined) return;
    var base = type.replace(/\[\d+\]$/, "");
    if (SETTERS[base]) {
      var loc = gl.getUniformLocation(prog, name);
      if (loc === null && base !== type) loc = gl.getUniformLocation(prog, name + "[0]");
      if (loc !== null) SETTERS[base](loc, value);
      return;
    }
    var members = known[base];
    if (!members) return;
    var items = base !== type ? value : [value];
    for (var i = 0; i < items.length; i++) {
      var prefix = base !== type ? name + "[" + i + "]" : name;
      var item = items[i];
      for (var k = 0; k < members.length; k++) {
        var mv = Array.isArray(item) ? item[k] : item && item[members[k][1]];
        setUniform(prog, known, prefix + "." + members[k][1], members[k][0], mv);
      }
    }
  }

  // ------------------------------------------------------------ camera (render.py's look_at and perspective)
  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function normalize(a) { var n = Math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); return [a[0] / n, a[1] / n, a[2] / n]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  // 4x4 as rows (m[r][c]); uploaded column-major
  function lookAt(eye, target, up) {
    var f = normalize(sub(target, eye)), s = normalize(cross(f, up)), u = cross(s, f);
    return [[s[0], s[1], s[2], -dot(s, eye)], [u[0], u[1], u[2], -dot(u, eye)],
            [-f[0], -f[1], -f[2], dot(f, eye)], [0, 0, 0, 1]];
  }
  function perspective(fovY, aspect, near, far) {
    var f = 1.0 / Math.tan(fovY * Math.PI / 180.0 / 2.0);
    return [[f / aspect, 0, 0, 0], [0, f, 0, 0],
            [0, 0, (far + near) / (near - far), 2.0 * far * near / (near - far)], [0, 0, -1, 0]];
  }
  function mul(a, b) {
    var out = [];
    for (var r = 0; r < 4; r++) {
      out.push([]);
      for (var c = 0; c < 4; c++) {
        var s = 0;
        for (var k = 0; k < 4; k++) s += a[r][k] * b[k][c];
        out[r].push(s);
      }
    }
    return out;
  }
  function columnMajor(m) {
    var out = [];
    for (var c = 0; c < 4; c++) for (var r = 0; r < 4; r++) out.push(m[r][c]);
    return out;
  }
  var IDENTITY = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];

  // orbit about the target: render's camera is distance |eye - target|, azimuth and elevation of eye - target
  var cam = data.camera;
  var home = (function () {
    var d = sub(cam.eye, cam.target), r = Math.sqrt(dot(d, d));
    return { radius: r, azimuth: Math.atan2(d[0], d[2]), elevation: Math.asin(d[1] / r) };
  })();
  var orbit = { radius: home.radius, azimuth: home.azimuth, elevation: home.elevation };
  function eyePosition() {
    if (orbit.radius === home.radius && orbit.azimuth === home.azimuth && orbit.elevation === home.elevation)
      return cam.eye.slice();  // render's camera exactly, not its round trip through trigonometry
    var ce = Math.cos(orbit.elevation);
    return [cam.target[0] + orbit.radius * ce * Math.sin(orbit.azimuth),
            cam.target[1] + orbit.radius * Math.sin(orbit.elevation),
            cam.target[2] + orbit.radius * ce * Math.cos(orbit.azimuth)];
  }

  // ------------------------------------------------------------ setup
  var size = data.size, prog, encodeProg, vao, indexType, count, units = [], fbo, colour, known;
  try {
    prog = link(data.vertex, data.fragment, "element " + data.element);
    encodeProg = link(ENCODE_VS, ENCODE_FS, "the sRGB encode pass");
    vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    var geo = data.geometry;
    for (var name in geo.attributes) {
      var loc = gl.getAttribLocation(prog, name);
      if (loc < 0) continue;
      var b = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(bytes(geo.attributes[name].data)), gl.STATIC_DRAW);
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, geo.attributes[name].size, gl.FLOAT, false, 0, 0);
    }
    var ib = gl.createBuffer();
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ib);
    var index = geo.index_type === "u16" ? new Uint16Array(bytes(geo.index)) : new Uint32Array(bytes(geo.index));
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, index, gl.STATIC_DRAW);
    indexType = geo.index_type === "u16" ? gl.UNSIGNED_SHORT : gl.UNSIGNED_INT;
    count = geo.count;
    gl.bindVertexArray(null);

    // texture units as render binds them: the environment, its irradiance, then the material's samplers
    units.push(["u_envRadiance", makeTexture(data.environment.radiance)]);
    /*PREFILTER*/
    units.push(["u_envIrradiance", makeTexture(data.environment.irradiance)]);
    var images = data.textures.images.map(function (img) { return makeTexture(img); });
    Object.keys(data.textures.samplers).sort().forEach(function (name) {
      units.push([name, images[data.textures.samplers[name]]]);
    });
    // a sampler left without a texture reads transparent black on a unit of its own
    var empty = makeTexture({ width: 1, height: 1, channels: 4, type: "f32", levels: [btoa("\0".repeat(16))] });
    var bound = {};
    units.forEach(function (u) { bound[u[0]] = true; });
    var n = gl.getProgramParameter(prog, gl.ACTIVE_UNIFORMS);
    for (var i = 0; i < n; i++) {
      var info = gl.getActiveUniform(prog, i);
      if (info.type === gl.SAMPLER_2D && !bound[info.name]) units.push([info.name, empty]);
    }

    colour = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, colour);
    gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, size, size);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    var depth = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, depth);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, size, size);
    fbo = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, colour, 0);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depth);
    if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE)
      throw new Error("the float framebuffer is not complete on this browser");
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);

    // the material's public inputs, from the manifest's values (ES has no uniform initializers)
    gl.useProgram(prog);
    known = structs(data.vertex + "\n" + data.fragment);
    data.uniforms.concat(data.application).forEach(function (u) {  // the manifest's member lists, where given
      if (u.members) known[u.type.replace(/\[\d+\]$/, "")] = u.members.map(function (m) { return [m.type, m.name]; });
    });
    data.uniforms.forEach(function (u) { setUniform(prog, known, u.name, u.type, u.value); });
  } catch (e) {
    fail("mtlxgen: " + (e && e.message ? e.message : e));
    return;
  }

  // ------------------------------------------------------------ drawing
  function draw(samples) {
    var eye = eyePosition();
    var view = lookAt(eye, cam.target, cam.up);
    var viewProjection = mul(perspective(cam.fov_y, 1.0, cam.near, cam.far), view);
    var app = {  // what render.Renderer.bind sets; every other application uniform keeps its default
      u_worldMatrix: IDENTITY, u_viewProjectionMatrix: columnMajor(viewProjection),
      u_worldInverseTransposeMatrix: IDENTITY, u_worldInverseMatrix: IDENTITY,
      u_envMatrix: data.environment.matrix, u_viewPosition: eye,
      u_envRadianceMips: data.environment.mips, u_envRadianceSamples: samples,
      u_envLightIntensity: 1.0, u_numActiveLightSources: 0, u_envSampleFrame: 0, u_envSampleFrames: 1
    };
    gl.useProgram(prog);
    data.application.forEach(function (u) {
      if (/^sampler/.test(u.type)) return;
      setUniform(prog, known, u.name, u.type, u.name in app ? app[u.name] : u["default"]);
    });
    units.forEach(function (u, unit) {
      var loc = gl.getUniformLocation(prog, u[0]);
      if (loc === null) return;
      gl.activeTexture(gl.TEXTURE0 + unit);
      gl.bindTexture(gl.TEXTURE_2D, u[1]);
      gl.uniform1i(loc, unit);
    });
    gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
    gl.viewport(0, 0, size, size);
    gl.disable(gl.BLEND);
    gl.disable(gl.CULL_FACE);
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LESS);
    gl.depthMask(true);
    gl.clearColor(0, 0, 0, 0);
    gl.clearDepth(1.0);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.bindVertexArray(vao);
    gl.drawElements(gl.TRIANGLES, count, indexType, 0);
    gl.bindVertexArray(null);

    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, size, size);
    gl.disable(gl.DEPTH_TEST);
    gl.useProgram(encodeProg);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, colour);
    gl.uniform1i(gl.getUniformLocation(encodeProg, "u_image"), 0);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    state.frames++;
  }

  // full sample count when still; a quick preview while dragging
  var PREVIEW_SAMPLES = 8, pending = false, settle = null;
  function redraw(quick) {
    if (!pending) {
      pending = true;
      requestAnimationFrame(function () {
        pending = false;
        draw(quick ? Math.min(PREVIEW_SAMPLES, data.samples) : data.samples);
      });
    }
    clearTimeout(settle);
    if (quick) settle = setTimeout(function () { redraw(false); }, 200);
  }
  var dragging = null;
  canvas.addEventListener("pointerdown", function (e) {
    dragging = { x: e.clientX, y: e.clientY };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener("pointermove", function (e) {
    if (!dragging) return;
    var scale = Math.PI / canvas.clientHeight;
    orbit.azimuth -= (e.clientX - dragging.x) * scale;
    orbit.elevation = Math.max(-1.55, Math.min(1.55, orbit.elevation + (e.clientY - dragging.y) * scale));
    dragging = { x: e.clientX, y: e.clientY };
    redraw(true);
  });
  function release() { dragging = null; }
  canvas.addEventListener("pointerup", release);
  canvas.addEventListener("pointercancel", release);
  canvas.addEventListener("wheel", function (e) {
    e.preventDefault();
    orbit.radius = Math.max(cam.near * 2.0, Math.min(cam.far * 0.5, orbit.radius * Math.exp(e.deltaY * 0.001)));
    redraw(true);
  }, { passive: false });
  canvas.addEventListener("dblclick", function () {
    orbit.radius = home.radius; orbit.azimuth = home.azimuth; orbit.elevation = home.elevation;
    redraw(false);
  });

  state.draw = function (samples) { draw(samples || data.samples); };
  state.orbit = orbit;
  state.pixels = function () {  // the canvas's RGBA8, rows top first, base64
    var px = new Uint8Array(size * size * 4), row = size * 4, out = new Uint8Array(px.length);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.readPixels(0, 0, size, size, gl.RGBA, gl.UNSIGNED_BYTE, px);
    for (var y = 0; y < size; y++) out.set(px.subarray((size - 1 - y) * row, (size - y) * row), y * row);
    var s = "";
    for (var i = 0; i < out.length; i += 0x8000) s += String.fromCharCode.apply(null, out.subarray(i, i + 0x8000));
    return btoa(s);
  };
  try {
    draw(data.samples);
    var err = gl.getError();
    if (err !== gl.NO_ERROR) throw new Error("WebGL error 0x" + err.toString(16) + " while drawing");
  } catch (e) {
    fail("mtlxgen: " + (e && e.message ? e.message : e));
    return;
  }
  state.ready = true;
})();
