"""Image comparison: the parity metric shared with the scoreboard.

Two sRGB 8-bit renders match when the mean of the per-pixel max-channel difference is <= 2/255 and
at most 1% of pixels differ by more than 8/255.
"""
from mtlxgen.base.records import dataclass

import numpy as np

from mtlxgen.base.images import to_srgb8

MEAN_LIMIT = 2.0
PIXEL_THRESHOLD = 8
FRACTION_LIMIT = 0.01


@dataclass(frozen=True)
class Parity:
    mean: float          # mean max-channel difference, in 8-bit steps
    fraction: float      # share of pixels off by more than PIXEL_THRESHOLD
    max: int

    @property
    def passes(self):
        return self.mean <= MEAN_LIMIT and self.fraction <= FRACTION_LIMIT

    def __str__(self):
        return "mean %.2f/255, %.2f%% of pixels > %d/255, max %d" % (self.mean, 100 * self.fraction,
                                                                     PIXEL_THRESHOLD, self.max)


def diff_map(a, b, channels=3):
    """Per-pixel max-channel difference of two images (linear float, or sRGB uint8), in 8-bit sRGB steps."""
    a8 = a if a.dtype == np.uint8 else to_srgb8(a)
    b8 = b if b.dtype == np.uint8 else to_srgb8(b)
    return np.abs(a8[..., :channels].astype(np.int16) - b8[..., :channels].astype(np.int16)).max(-1)


def parity(a, b):
    """Compare two images (linear float RGBA, or sRGB uint8) on their RGB channels."""
    d = diff_map(a, b)
    return Parity(float(d.mean()), float((d > PIXEL_THRESHOLD).mean()), int(d.max()))
