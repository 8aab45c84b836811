#!/usr/bin/env python3
"""Value of a pixel next to a hard edge under Mitsuba 3's default `gaussian` rfilter
(stddev 0.5, radius 2), exact and as Mitsuba's scalar film splats it (`eval_discretized`:
a 31-step table, each step the filter's value at its near end; rfilter.h / rfilter.cpp).

Measures the projector scenes' edge pixels (docs/conformance.md): the constant projector's
lit square starts `d` pixels from the centre of the last dark column's pixel (d = 0.552 for
fov 165 seen at fov 170 over 48 pixels: 24 - 48 tan(82.5) / (2 tan(85)) = 8.052, pixel 7's
centre 7.5). A pixel is the filter-weighted mean of its samples, normalised by the weights,
so in the continuous limit it is the filter's mass beyond d over its whole mass.
Usage: python3 scripts/mitsuba_filter_edge.py
"""
import math

STDDEV, RADIUS, RES = 0.5, 2.0, 31


def gauss(x):
    alpha = -1.0 / (2.0 * STDDEV * STDDEV)
    return max(0.0, math.exp(alpha * x * x) - math.exp(alpha * RADIUS * RADIUS))


TABLE = [gauss(RADIUS * i / RES) for i in range(RES)] + [0.0]


def discretized(x):
    return TABLE[min(int(abs(x) * RES / RADIUS), RES)]


def mass(f, lo, hi, n=200000):
    h = (hi - lo) / n
    return sum(f(lo + (i + 0.5) * h) for i in range(n)) * h


def main():
    d = 24 - 48 * math.tan(math.radians(82.5)) / (2 * math.tan(math.radians(85))) - 7.5
    for name, f in (("exact gaussian", gauss), ("Mitsuba's discretized", discretized)):
        edge = mass(f, d, RADIUS) / mass(f, -RADIUS, RADIUS)
        inner = mass(f, d - 1, RADIUS) / mass(f, -RADIUS, RADIUS)
        print(f"{name:24s}: d = {d:.4f}; dark pixel {edge:.4f}, next pixel {inner:.4f}")


if __name__ == "__main__":
    main()
