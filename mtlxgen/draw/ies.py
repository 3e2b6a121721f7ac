"""IES LM-63 photometric files (IES LM-63-1995 / -2002) -> a 2-D intensity texture for measured_edf.

parse(path) reads the header keywords, TILT, the photometric numbers, the vertical and horizontal
angles and the candela table (numbers separated by blanks or commas, across any line breaks).
Candelas are scaled by the candela multiplier and the ballast factor. Only type C photometry (the
kind luminaires of buildings use: vertical angle 0 = the luminaire's axis) is accepted.

texture(profile) resamples it over the whole sphere, with the symmetries LM-63 implies for the
horizontal angles given (one angle: symmetric about the axis; 0-90: quadrants; 0-180: bilateral;
0-360: none), and normalises by the peak: rows are vertical angles 0..180° (height rows, ends
included), columns horizontal angles 0..360° (width columns, 360° excluded). Vertical angles outside
those measured are dark. glsl_lib/pbrlib/edf/measured.glsl reads it; the render harness binds a
texture whose file ends in .ies through this module.
"""
import re
from mtlxgen.base.records import dataclass

import numpy as np

from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.base.files import check_regular, read_bounded

WIDTH, HEIGHT = 64, 91          # texture: horizontal x vertical samples


@dataclass
class Profile:
    path: str
    keywords: dict               # [TEST], [MANUFAC], ... -> text
    lumens_per_lamp: float
    multiplier: float
    photometric_type: int        # 1 = C, 2 = B, 3 = A
    units: int                   # 1 = feet, 2 = metres
    size: tuple                  # width, length, height of the luminous opening
    ballast_factor: float
    input_watts: float
    vertical: np.ndarray         # degrees, ascending
    horizontal: np.ndarray       # degrees, ascending
    candela: np.ndarray          # [horizontal, vertical], multiplier and ballast factor applied

    @property
    def peak(self):
        return float(self.candela.max()) if self.candela.size else 0.0


def _tokens(lines, first_line):
    """(value text, line number) of every number after the header, in order."""
    for k, line in enumerate(lines):
        for tok in re.split(r"[\s,]+", line.strip()):
            if tok:
                yield tok, first_line + k


def parse(path):
    # regular files only, size capped on the file's size before reading (a document names the profile: it may
    # point at /dev/zero, a FIFO or a huge sparse file)
    check_regular(path, Loc(path, 0), "IES file", "text")
    lines = read_bounded(path, Loc(path, 0), "IES file").decode("latin-1").splitlines()
    if not lines:
        raise MtlxError((Loc(path, 1), "empty IES file"))
    keywords, i = {}, 0
    if lines[0].strip().upper().startswith("IESNA"):
        i = 1
    tilt_line = None
    while i < len(lines):
        s = lines[i].strip()
        i += 1
        m = re.match(r"\[([^\]]+)\]\s*(.*)", s)
        if m:
            keywords[m.group(1).upper()] = (keywords.get(m.group(1).upper(), "") + " " + m.group(2)).strip()
            continue
        if s.upper().startswith("TILT="):
            tilt_line = (s[5:].strip().upper(), i)
            break
        if s:
            keywords.setdefault("_text", "")
    if tilt_line is None:
        raise MtlxError((Loc(path, len(lines)), "no TILT= line: not an IES LM-63 file"))
    toks = _tokens(lines[i:], i + 1)
    last = [i]

    def number(what, integer=False):
        try:
            tok, line = next(toks)
        except StopIteration:
            raise MtlxError((Loc(path, last[0]), "IES file ends before %s" % what)) from None
        last[0] = line
        try:
            v = float(tok)
        except ValueError:
            raise MtlxError((Loc(path, line), "IES %s: '%s' is not a number" % (what, tok))) from None
        if integer:
            if v != int(v):
                raise MtlxError((Loc(path, line), "IES %s: '%s' is not a whole number" % (what, tok)))
            return int(v)
        return v

    if tilt_line[0] == "INCLUDE":      # lamp-to-luminaire geometry, then angle / multiplier pairs
        number("the TILT lamp geometry", integer=True)
        n = number("the number of TILT angles", integer=True)
        for _ in range(2 * n):
            number("the TILT table")
    lamps = number("the number of lamps", integer=True)
    lumens = number("the lumens per lamp")
    multiplier = number("the candela multiplier")
    n_vert = number("the number of vertical angles", integer=True)
    line_nv = last[0]
    n_horiz = number("the number of horizontal angles", integer=True)
    ptype = number("the photometric type", integer=True)
    line_type = last[0]
    units = number("the units type", integer=True)
    size = (number("the luminous width"), number("the luminous length"), number("the luminous height"))
    ballast = number("the ballast factor")
    number("the ballast-lamp photometric factor")
    watts = number("the input watts")
    if lamps < 1:
        pass                               # -1 marks absolute photometry: nothing to change here
    if n_vert < 1 or n_horiz < 1:
        raise MtlxError((Loc(path, line_nv), "IES file gives %d vertical and %d horizontal angles; "
                                             "it needs at least one of each" % (n_vert, n_horiz)))
    if ptype != 1:
        raise MtlxError((Loc(path, line_type), "IES photometric type %d (%s) is not supported: only type C (1)"
                         % (ptype, {2: "B", 3: "A"}.get(ptype, "unknown"))))
    vertical = np.array([number("the vertical angles") for _ in range(n_vert)])
    line_v = last[0]
    horizontal = np.array([number("the horizontal angles") for _ in range(n_horiz)])
    line_h = last[0]
    candela = np.array([number("the candela values") for _ in range(n_vert * n_horiz)]).reshape(n_horiz, n_vert)
    if np.any(np.diff(vertical) <= 0) or vertical[0] < 0 or vertical[-1] > 180:
        raise MtlxError((Loc(path, line_v), "IES vertical angles must ascend within 0..180 degrees"))
    if np.any(np.diff(horizontal) <= 0) or horizontal[0] < 0 or horizontal[-1] > 360:
        raise MtlxError((Loc(path, line_h), "IES horizontal angles must ascend within 0..360 degrees"))
    return Profile(path, keywords, lumens, multiplier, ptype, units, size, ballast, watts, vertical, horizontal,
                   candela * multiplier * ballast)


def _full_circle(profile):
    """Horizontal angles and candela rows over 0..360 (360 included), by LM-63's symmetries."""
    h, c = profile.horizontal, profile.candela
    if len(h) == 1:
        return np.array([0.0, 360.0]), np.concatenate([c, c])
    last = h[-1]
    if abs(last - 90.0) < 1e-6:            # quadrant symmetric: mirror to 180, then to 360
        h, c = np.concatenate([h, 180.0 - h[-2::-1]]), np.concatenate([c, c[-2::-1]])
        last = 180.0
    if abs(last - 180.0) < 1e-6:           # bilateral about the 0-180 plane
        h, c = np.concatenate([h, 360.0 - h[-2::-1]]), np.concatenate([c, c[-2::-1]])
    if h[0] > 0.0 or h[-1] < 360.0:        # close the circle
        h, c = np.concatenate([h, [h[0] + 360.0]]), np.concatenate([c, c[:1]])
    return h, c


def intensity(profile, theta_deg, phi_deg):
    """Candela toward vertical angle theta, horizontal angle phi (degrees; arrays broadcast),
    interpolated bilinearly; 0 outside the measured vertical range."""
    h, c = _full_circle(profile)
    theta, phi = np.broadcast_arrays(np.asarray(theta_deg, float), np.mod(np.asarray(phi_deg, float), 360.0))
    v = profile.vertical
    if h[0] > 0.0:
        phi = np.where(phi < h[0], phi + 360.0, phi)
    # along phi: rows of c; along theta: columns
    j = np.clip(np.searchsorted(h, phi, side="right") - 1, 0, len(h) - 2)
    tphi = (phi - h[j]) / (h[j + 1] - h[j])
    if len(v) == 1:
        row = c[j, 0] * (1 - tphi) + c[j + 1, 0] * tphi
        return np.where(np.abs(theta - v[0]) < 1e-6, row, 0.0)
    k = np.clip(np.searchsorted(v, theta, side="right") - 1, 0, len(v) - 2)
    tth = np.clip((theta - v[k]) / (v[k + 1] - v[k]), 0.0, 1.0)
    a = c[j, k] * (1 - tth) + c[j, k + 1] * tth
    b = c[j + 1, k] * (1 - tth) + c[j + 1, k + 1] * tth
    out = a * (1 - tphi) + b * tphi
    return np.where((theta < v[0] - 1e-6) | (theta > v[-1] + 1e-6), 0.0, out)


def texture(profile, width=WIDTH, height=HEIGHT):
    """float32 [height, width, 1]: intensity / peak; row r at vertical angle 180 r / (height - 1),
    column q at horizontal angle 360 q / width."""
    theta = np.linspace(0.0, 180.0, height)[:, None]
    phi = (np.arange(width) * 360.0 / width)[None, :]
    img = intensity(profile, theta, phi)
    peak = profile.peak
    img = img / peak if peak > 0 else np.zeros_like(img)
    return img.astype(np.float32)[..., None]


def load_texture(path):
    return texture(parse(path))
