"""Renders a scene with gpu_photon and shows it with matplotlib (or saves it with --out).

    python examples/python/render_and_plot.py [SCENE] [--spp N] [--passes N] [--out FILE.png]
"""

import argparse

import matplotlib

import gpu_photon


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scene", nargs="?", default="scenes/cornell-box.toml")
    p.add_argument("--spp", type=int, default=16)
    p.add_argument("--passes", type=int, default=4)
    p.add_argument("--backend", default="auto")
    p.add_argument("--out", help="write the figure here instead of showing it")
    args = p.parse_args()
    if args.out:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scene = gpu_photon.load(args.scene)
    image = scene.render(spp=args.spp, passes=args.passes, backend=args.backend)
    srgb = image.clip(0, None) ** (1 / 2.2)  # a display gamma; write_png does exact sRGB
    plt.imshow(srgb.clip(0, 1))
    plt.title(f"{args.scene}: {args.passes} passes x {args.spp} spp, mean {image.mean():.4f}")
    plt.axis("off")
    if args.out:
        plt.savefig(args.out, dpi=100, bbox_inches="tight")
    else:
        plt.show()


if __name__ == "__main__":
    main()
