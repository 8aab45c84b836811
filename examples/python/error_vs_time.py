"""Sweeps one setting and plots error against render time, one curve per value: each curve is
a progressive render measured after every pass against a reference image (by default
tests/data/cornell-diffuse.exr, Mitsuba 3's path-traced Cornell box).

    python examples/python/error_vs_time.py [--setting photons] [--values 20000,50000,200000]
        [--scene scenes/cornell-box.toml] [--reference tests/data/cornell-diffuse.exr]
        [--passes 8] [--size 64] [--out error.png]

--size renders at that width (the reference is averaged down by an integer factor to match).
"""

import argparse

import matplotlib

import gpu_photon


def curve(scene, reference, settings, passes, backend):
    """(seconds, RMSE) after every pass of a progressive render with keyword `settings`."""
    h, w, _ = reference.shape
    r = gpu_photon.Renderer(scene, backend=backend, width=w, height=h, passes=passes, **settings)
    points = []

    def measure(info):
        points.append((info["elapsed"], gpu_photon.diff(info["image"], reference)["rmse"]))

    r.run(measure)
    return points


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scene", default="scenes/cornell-box.toml")
    p.add_argument("--reference", default="tests/data/cornell-diffuse.exr")
    p.add_argument("--setting", default="photons")
    p.add_argument("--values", default="20000,50000,200000")
    p.add_argument("--passes", type=int, default=8)
    p.add_argument("--spp", type=int, default=4)
    p.add_argument("--size", type=int, help="render width (default: the reference's)")
    p.add_argument("--backend", default="auto")
    p.add_argument("--out", help="write the figure here instead of showing it")
    args = p.parse_args()
    if args.out:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scene = gpu_photon.load(args.scene)
    reference = gpu_photon.read_image(args.reference)
    if args.size:
        h, w, _ = reference.shape
        f = w // args.size
        reference = reference[: h - h % f, : w - w % f]
        reference = reference.reshape(h // f, f, w // f, f, 3).mean(axis=(1, 3))
    for text in args.values.split(","):
        value = float(text) if "." in text else int(text)
        settings = {args.setting: value}
        if args.setting != "spp":
            settings["spp"] = args.spp
        t, e = zip(*curve(scene, reference, settings, args.passes, args.backend))
        plt.loglog(t, e, "o-", label=f"{args.setting} = {value}")
        print(f"{args.setting} = {value}: RMSE {e[-1]:.5f} after {t[-1]:.2f} s")
    plt.xlabel("wall time (s)")
    plt.ylabel("RMSE against the reference")
    plt.title(f"{args.scene}: error against time")
    plt.legend()
    if args.out:
        plt.savefig(args.out, dpi=100, bbox_inches="tight")
    else:
        plt.show()


if __name__ == "__main__":
    main()
