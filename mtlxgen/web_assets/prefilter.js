    // the GGX-prefiltered radiance map (manifest "environment": "prefiltered"; PREFILTER_RECIPE, as
    // environment.Prefilter makes it for render): a float texture of the map's mip sizes, each level drawn by
    // the prefilter shader (data.prefilter: prefilter_sources("essl")) from the box chain just uploaded, into a
    // framebuffer on that level. Without EXT_color_buffer_float the box chain is bound instead (a warning).
    var prefilterRadiance = function (source, env, pre) {
      if (!gl.getExtension("EXT_color_buffer_float")) {
        console.warn("mtlxgen: no EXT_color_buffer_float: the environment is box-filtered, not GGX-prefiltered");
        return source;
      }
      var program = link(pre.vertex, pre.fragment, "prefilter");
      var w = env.radiance.width, h = env.radiance.height, sizes = [[w, h]];
      while (sizes[sizes.length - 1][0] > 1 || sizes[sizes.length - 1][1] > 1) {
        var last = sizes[sizes.length - 1];
        sizes.push([Math.max(1, last[0] >> 1), Math.max(1, last[1] >> 1)]);
      }
      var out = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D, out);
      // 32-bit floats filter linearly only with OES_texture_float_linear: else 16-bit floats
      gl.texStorage2D(gl.TEXTURE_2D, sizes.length, floatLinear ? gl.RGBA32F : gl.RGBA16F, w, h);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR_MIPMAP_LINEAR);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.REPEAT);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);   // the poles never blend
      gl.bindTexture(gl.TEXTURE_2D, source);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);   // as render's pass reads it
      var target = gl.createFramebuffer();
      var vao = gl.createVertexArray();
      gl.useProgram(program);
      gl.activeTexture(gl.TEXTURE0);
      gl.uniform1i(gl.getUniformLocation(program, "u_source"), 0);
      gl.uniform1i(gl.getUniformLocation(program, "u_sourceMips"), sizes.length);
      gl.uniform1i(gl.getUniformLocation(program, "u_samples"), pre.samples);
      gl.disable(gl.BLEND);
      gl.disable(gl.DEPTH_TEST);
      gl.bindVertexArray(vao);
      gl.bindFramebuffer(gl.FRAMEBUFFER, target);
      for (var level = 0; level < sizes.length; level++) {
        gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, out, level);
        if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) {
          console.warn("mtlxgen: a prefiltered level is not a complete framebuffer here: the environment is " +
                       "box-filtered, not GGX-prefiltered");
          out = null;
          break;
        }
        gl.viewport(0, 0, sizes[level][0], sizes[level][1]);
        gl.uniform1i(gl.getUniformLocation(program, "u_level"), level);
        gl.bindTexture(gl.TEXTURE_2D, source);
        gl.drawArrays(gl.TRIANGLES, 0, 3);
      }
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      gl.bindVertexArray(null);
      gl.deleteVertexArray(vao);
      gl.deleteFramebuffer(target);
      gl.deleteProgram(program);
      gl.bindTexture(gl.TEXTURE_2D, source);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.REPEAT);
      return out || source;
    };
    if (data.prefilter) units[0][1] = prefilterRadiance(units[0][1], data.environment, data.prefilter);
