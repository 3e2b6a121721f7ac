"""The viewer's property panel (imgui-bundle, drawn with moderngl): the shown element's public inputs grouped by
node and uifolder (docedit.public_inputs), sliders within uimin/uimax (uisoftmin/uisoftmax first), colour
pickers, enums as lists, texture files as text fields. Changing one sets the uniform on the linked program (no
regeneration); "Save" writes the changed values back into the document (docedit.save_values). Above them: the
element, the problems, the sample count and frame time, and the keys.
"""
import ctypes
import os

import numpy as np

from mtlxgen.apps import docedit
from mtlxgen.base.diagnostics import MtlxError
from mtlxgen.apps.uniformvalues import initial_values, set_uniform

_VS = """#version 400
uniform mat4 u_projection;
in vec2 in_pos;
in vec2 in_uv;
in vec4 in_color;
out vec2 v_uv;
out vec4 v_color;
void main()
{
    v_uv = in_uv;
    v_color = in_color;
    gl_Position = u_projection * vec4(in_pos, 0.0, 1.0);
}
"""

_FS = """#version 400
uniform sampler2D u_texture;
in vec2 v_uv;
in vec4 v_color;
out vec4 out_color;
void main()
{
    out_color = v_color * texture(u_texture, v_uv);
}
"""


class ImguiRenderer:
    """Dear ImGui's draw lists with moderngl. Textures follow ImGui 1.92's protocol (the backend creates,
    updates and destroys the font atlas's textures when ImGui asks: ImGuiBackendFlags_RendererHasTextures)."""

    def __init__(self, ctx):
        from imgui_bundle import imgui
        import moderngl
        self.imgui, self.mgl, self.ctx = imgui, moderngl, ctx
        self.prog = ctx.program(vertex_shader=_VS, fragment_shader=_FS)
        self.vbo = ctx.buffer(reserve=imgui.VERTEX_SIZE * 4096, dynamic=True)
        self.ibo = ctx.buffer(reserve=imgui.INDEX_SIZE * 8192, dynamic=True)
        self.vao = ctx.vertex_array(self.prog, [(self.vbo, "2f 2f 4f1", "in_pos", "in_uv", "in_color")],
                                    index_buffer=self.ibo, index_element_size=imgui.INDEX_SIZE)
        self.textures = {}
        io = imgui.get_io()
        io.backend_flags |= imgui.BackendFlags_.renderer_has_textures
        pio = imgui.get_platform_io()
        pio.renderer_texture_max_width = pio.renderer_texture_max_height = ctx.info.get("GL_MAX_TEXTURE_SIZE", 4096)

    def _update_textures(self):
        imgui = self.imgui
        status = imgui.ImTextureStatus
        for tex in imgui.get_platform_io().textures:
            if tex.status == status.want_create or tex.status == status.want_updates:
                pixels = np.asarray(tex.get_pixels_array(), dtype=np.uint8).reshape(tex.height, tex.width, 4)
                t = self.textures.get(tex.tex_id) if tex.status == status.want_updates else None
                if t is None or t.size != (tex.width, tex.height):
                    t = self.ctx.texture((tex.width, tex.height), 4, pixels.tobytes())
                    t.filter = (self.mgl.LINEAR, self.mgl.LINEAR)
                    self.textures[t.glo] = t
                    tex.set_tex_id(t.glo)
                else:
                    t.write(pixels.tobytes())
                tex.status = status.ok
            elif tex.status == status.want_destroy and tex.unused_frames > 0:
                t = self.textures.pop(tex.tex_id, None)
                if t is not None:
                    t.release()
                tex.set_tex_id(0)
                tex.status = status.destroyed

    def render(self, draw_data, target):
        imgui = self.imgui
        self._update_textures()
        w, h = draw_data.display_size.x, draw_data.display_size.y
        if w <= 0 or h <= 0:
            return
        fb_w, fb_h = target.size if hasattr(target, "size") else (int(w), int(h))
        sx, sy = fb_w / w, fb_h / h
        x0, y0 = draw_data.display_pos.x, draw_data.display_pos.y
        proj = np.array([[2.0 / w, 0, 0, 0], [0, -2.0 / h, 0, 0], [0, 0, -1.0, 0],
                         [-(2 * x0 + w) / w, (2 * y0 + h) / h, 0, 1.0]], dtype="f4")
        self.prog["u_projection"].write(proj.tobytes())
        self.prog["u_texture"].value = 0
        ctx = self.ctx
        target.use()
        ctx.enable_only(self.mgl.BLEND)
        ctx.blend_equation = self.mgl.FUNC_ADD
        ctx.blend_func = (self.mgl.SRC_ALPHA, self.mgl.ONE_MINUS_SRC_ALPHA, self.mgl.ONE, self.mgl.ONE_MINUS_SRC_ALPHA)
        for commands in draw_data.cmd_lists:
            vsize = commands.vtx_buffer.size() * imgui.VERTEX_SIZE
            isize = commands.idx_buffer.size() * imgui.INDEX_SIZE
            if vsize > self.vbo.size:
                self.vbo.orphan(vsize * 2)
            if isize > self.ibo.size:
                self.ibo.orphan(isize * 2)
            self.vbo.write((ctypes.c_byte * vsize).from_address(commands.vtx_buffer.data_address()))
            self.ibo.write((ctypes.c_byte * isize).from_address(commands.idx_buffer.data_address()))
            for cmd in commands.cmd_buffer:
                t = self.textures.get(cmd.tex_ref.get_tex_id())
                if t is None or cmd.elem_count == 0:
                    continue
                t.use(0)
                cx, cy, cz, cw = cmd.clip_rect.x - x0, cmd.clip_rect.y - y0, cmd.clip_rect.z - x0, cmd.clip_rect.w - y0
                if cz <= cx or cw <= cy:
                    continue
                ctx.scissor = (int(cx * sx), int(fb_h - cw * sy), int((cz - cx) * sx), int((cw - cy) * sy))
                self.vao.render(self.mgl.TRIANGLES, vertices=cmd.elem_count, first=cmd.idx_offset)
        ctx.scissor = None
        ctx.disable(self.mgl.BLEND)

    def release(self):
        for t in self.textures.values():
            t.release()
        for x in (self.vao, self.vbo, self.ibo, self.prog):
            x.release()


class Panel:
    """The property panel over a GlfwWindow: feeds it glfw's input, draws it after the picture."""

    def __init__(self, viewer, window):
        from imgui_bundle import imgui
        self.imgui, self.viewer, self.window = imgui, viewer, window
        self.context = imgui.create_context()
        imgui.get_io().set_ini_filename("")         # no imgui.ini written next to the user's files
        imgui.style_colors_dark()
        self.renderer = ImguiRenderer(window.ctx)
        self._inputs_key = None
        self.inputs = []
        self.message = ""
        self._time = None
        self._keymap = self._make_keymap()

    # input from glfw
    def _make_keymap(self):
        import glfw
        k = self.imgui.Key
        table = {glfw.KEY_TAB: k.tab, glfw.KEY_LEFT: k.left_arrow, glfw.KEY_RIGHT: k.right_arrow,
                 glfw.KEY_UP: k.up_arrow, glfw.KEY_DOWN: k.down_arrow, glfw.KEY_HOME: k.home, glfw.KEY_END: k.end,
                 glfw.KEY_DELETE: k.delete, glfw.KEY_BACKSPACE: k.backspace, glfw.KEY_ENTER: k.enter,
                 glfw.KEY_KP_ENTER: k.keypad_enter, glfw.KEY_ESCAPE: k.escape, glfw.KEY_LEFT_CONTROL: k.left_ctrl,
                 glfw.KEY_RIGHT_CONTROL: k.right_ctrl, glfw.KEY_LEFT_SHIFT: k.left_shift,
                 glfw.KEY_RIGHT_SHIFT: k.right_shift, glfw.KEY_A: k.a, glfw.KEY_C: k.c, glfw.KEY_V: k.v,
                 glfw.KEY_X: k.x, glfw.KEY_Z: k.z}
        return table

    def wants(self, what):
        if not self.viewer.show_panel:
            return False
        io = self.imgui.get_io()
        return io.want_capture_mouse if what == "mouse" else io.want_capture_keyboard

    def mouse_pos(self, x, y):
        self.imgui.get_io().add_mouse_pos_event(float(x), float(y))

    def mouse_button(self, button, down):
        if button < 5:
            self.imgui.get_io().add_mouse_button_event(button, down)

    def scroll(self, dx, dy):
        self.imgui.get_io().add_mouse_wheel_event(float(dx), float(dy))

    def char(self, codepoint):
        self.imgui.get_io().add_input_character(codepoint)

    def key(self, key, action, mods):
        import glfw
        io = self.imgui.get_io()
        k = self._keymap.get(key)
        if k is not None and action in (glfw.PRESS, glfw.RELEASE):
            io.add_key_event(k, action == glfw.PRESS)
        io.add_key_event(self.imgui.Key.mod_ctrl, bool(mods & glfw.MOD_CONTROL))
        io.add_key_event(self.imgui.Key.mod_shift, bool(mods & glfw.MOD_SHIFT))

    # content
    def _refresh(self):
        v = self.viewer
        loaded = v.loaded.get(v.element)
        key = (v.element, v.generation, id(loaded.prepared) if loaded else None)
        if key == self._inputs_key:
            return
        self._inputs_key = key
        self.inputs = []
        if loaded is None or v.session is None or not hasattr(v.session, "graph"):
            return
        try:
            self.inputs = docedit.public_inputs(v.session, v.element)
        except MtlxError:
            self.inputs = []

    def value_of(self, item):
        loaded = self.viewer.loaded.get(self.viewer.element)
        if loaded is not None and item.uniform in loaded.overrides:
            return loaded.overrides[item.uniform]
        if loaded is not None and item.uniform in loaded.values:    # value edits since the session read it
            return loaded.values[item.uniform]
        return item.value

    def set_value(self, item, value):
        """A panel edit: the uniform set on the linked program (a texture's file rebound), kept as an override; an
        input the specialized shader folded into a constant is kept a uniform and the element generated again."""
        v = self.viewer
        loaded = v.loaded.get(v.element)
        if loaded is None:
            return
        if loaded.folded(item.uniform):         # a constant in the specialized shader: generated again, kept
            v.unfold(item.uniform, value)
            return
        loaded.overrides[item.uniform] = value
        if item.mtlx_type == "filename":
            from mtlxgen.base.resolve import resolve_file
            path = resolve_file(value, v.path) or value
            loaded.prepared.samplers = [(n, path if n == item.uniform else p, d)
                                        for n, p, d in loaded.prepared.samplers]
        else:
            set_uniform(loaded.prepared.prog, item.uniform,
                        tuple(value) if isinstance(value, (list, tuple)) else value)
        v.changed()

    def save(self):
        v = self.viewer
        loaded = v.loaded.get(v.element)
        if loaded is None or not loaded.overrides:
            self.message = "nothing changed"
            return []
        edits = [(item, loaded.overrides[item.uniform]) for item in self.inputs if item.uniform in loaded.overrides]
        if not edits:
            self.message = "nothing to save: the changed values are not inputs the document sets"
            return []
        try:
            written = docedit.save_values(edits)
        except MtlxError as e:          # one FILE:LINE line each; a refusal writes nothing (a failed write names
                                        # the files saved before it)
            lines = e.lines()
            for line in lines:
                v.say(line)
            self.message = lines[0] + (" (and %d more)" % (len(lines) - 1) if len(lines) > 1 else "")
            return []
        self.message = "saved %d value%s to %s" % (len(edits), "" if len(edits) == 1 else "s",
                                                   ", ".join(os.path.basename(p) for p in written))
        v.say(self.message)
        return written

    def revert(self):
        """Back to the document's values: the linked program's initial values and the manifest's texture files."""
        v = self.viewer
        loaded = v.loaded.get(v.element)
        if loaded is None:
            return
        values = dict(initial_values(loaded.generated.fragment), **loaded.values)
        for name in loaded.overrides:
            if name in values:
                set_uniform(loaded.prepared.prog, name, values[name])
        files = {t["uniform"]: t.get("file") for t in loaded.generated.manifest.get("textures", [])}
        loaded.prepared.samplers = [(n, files.get(n, p), d) for n, p, d in loaded.prepared.samplers]
        loaded.overrides.clear()
        v.changed()
        self.message = "reverted"

    def _widget(self, item):
        imgui = self.imgui
        label = "%s##%s" % (item.label, item.uniform)
        value = self.value_of(item)
        ui = item.ui
        t = item.mtlx_type

        def bounds(default_lo, default_hi):
            lo = ui.get("uisoftmin", ui.get("uimin"))
            hi = ui.get("uisoftmax", ui.get("uimax"))
            first = lambda x: x[0] if isinstance(x, (list, tuple)) else x
            lo = default_lo if lo is None else first(lo)
            hi = default_hi if hi is None else first(hi)
            return (lo, hi) if hi > lo else (default_lo, default_hi)

        changed, new = False, value
        if t == "float":
            lo, hi = bounds(0.0, max(1.0, float(value) * 2.0 if value else 1.0))
            changed, new = imgui.slider_float(label, float(value), float(lo), float(hi))
        elif t == "integer" and item.enum:
            values = [int(x) for x in item.enumvalues] if item.enumvalues and len(item.enumvalues) == len(
                item.enum) and all(x.lstrip("-").isdigit() for x in item.enumvalues) else list(range(len(item.enum)))
            current = values.index(value) if value in values else 0
            changed, index = imgui.combo(label, current, item.enum)
            new = values[index]
        elif t == "integer":
            lo, hi = bounds(0, max(10, int(value) * 2))
            changed, new = imgui.slider_int(label, int(value), int(lo), int(hi))
        elif t == "boolean":
            changed, new = imgui.checkbox(label, bool(value))
        elif t == "color3":
            changed, new = imgui.color_edit3(label, list(value), imgui.ColorEditFlags_.float | imgui.ColorEditFlags_.hdr)
        elif t == "color4":
            changed, new = imgui.color_edit4(label, list(value), imgui.ColorEditFlags_.float | imgui.ColorEditFlags_.hdr)
        elif t in ("vector2", "vector3", "vector4"):
            fn = {"vector2": imgui.drag_float2, "vector3": imgui.drag_float3, "vector4": imgui.drag_float4}[t]
            changed, new = fn(label, list(value), 0.01)
        elif t == "filename":
            changed, new = imgui.input_text(label, str(value or ""), imgui.InputTextFlags_.enter_returns_true)
        if changed:
            self.set_value(item, tuple(new) if isinstance(new, list) else new)

    def build(self):
        imgui, v = self.imgui, self.viewer
        width = 290                 # at the right edge, clear of the object in the middle
        display_w = imgui.get_io().display_size.x
        imgui.set_next_window_pos((max(display_w - width - 8, 8), 8), imgui.Cond_.first_use_ever)
        imgui.set_next_window_size((width, min(620, max(200, imgui.get_io().display_size.y - 16))),
                                   imgui.Cond_.first_use_ever)
        imgui.begin("%s##panel" % os.path.basename(v.display_path))
        imgui.push_item_width(imgui.get_window_width() * 0.5)      # room for the labels beside the widgets
        if v.elements:
            current = v.elements.index(v.element) if v.element in v.elements else 0
            changed, index = imgui.combo("element", current, v.elements)
            if changed and index != current:
                v.cycle_element(index - current)
        imgui.text("%s: %s" % (v.environment_method, v.sample_status()))
        imgui.text("frame %.1f ms" % (v.frame_time * 1000.0))
        for line in v.problems:
            imgui.text_colored(imgui.ImVec4(1.0, 0.45, 0.4, 1.0), line)
        if imgui.collapsing_header("keys"):
            for k, what in v.keys:
                imgui.text("%-16s %s" % (k, what))
        self._refresh()
        loaded = v.loaded.get(v.element)
        if self.inputs:
            if imgui.button("Save"):
                self.save()
            imgui.same_line()
            if imgui.button("Revert") and loaded is not None:
                self.revert()
            if self.message:
                imgui.same_line()
                imgui.text(self.message)
        groups = {}
        for item in self.inputs:
            groups.setdefault(item.group, []).append(item)
        for k, (group, items) in enumerate(groups.items()):
            if imgui.collapsing_header(group, imgui.TreeNodeFlags_.default_open if k == 0 or len(groups) <= 3 else 0):
                for item in items:
                    self._widget(item)
        imgui.pop_item_width()
        imgui.end()

    def draw(self, target):
        import time
        imgui = self.imgui
        imgui.set_current_context(self.context)
        io = imgui.get_io()
        w, h = self.window.glfw.get_window_size(self.window.window)
        io.display_size = (max(w, 1), max(h, 1))
        fb = self.window.framebuffer_size()
        io.display_framebuffer_scale = (fb[0] / max(w, 1), fb[1] / max(h, 1))
        now = time.perf_counter()
        io.delta_time = max(now - self._time, 1e-4) if self._time is not None else 1.0 / 60.0
        self._time = now
        imgui.new_frame()
        self.build()
        imgui.render()
        self.renderer.render(imgui.get_draw_data(), target)

    def release(self):
        self.renderer.release()
        self.imgui.destroy_context(self.context)
