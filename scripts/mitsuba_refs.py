"""What the reference scripts share: Mitsuba renders in two independent halves and the
16 x 16-block RMSE they report. Imported by envlight_reference.py, filter_reference.py and
cornell_spectra.py (run them from anywhere: they put this directory on the path)."""
import time
import numpy as np
import mitsuba as mi


def block_rmse(a, b, n=16):
    """RMSE of the n x n block means of the channel-mean difference of images a and b."""
    h, w, _ = a.shape
    d = (a - b).mean(axis=2)
    blocks = d[: h // n * n, : w // n * n].reshape(h // n, n, w // n, n).mean(axis=(1, 3))
    return float(np.sqrt((blocks ** 2).mean()))


def render_halves(scene_file, spp, chunk=None, times=None):
    """Two renders of scene_file at spp samples per pixel with seeds 1 and 2 (in the variant
    already set), as float64 (h, w, 3) arrays, and the mean per channel of their ratio.

    With chunk (a divisor of spp), each half is the mean of spp / chunk renders of chunk
    samples, half h's k-th with seed h + 2k (half 1: seeds 1, 3, 5, ...; half 2: 2, 4, 6, ...:
    all distinct, so the halves stay independent): a JIT variant traces all of a render's
    samples as one wavefront, whose memory grows with spp. With times (a list), each half's
    seconds (scene loading and all its renders) are appended to it."""
    chunk = chunk or spp
    if spp % chunk:
        raise ValueError(f"chunk {chunk} does not divide spp {spp}")
    halves = []
    for seed in (1, 2):
        start = time.perf_counter()
        scene = mi.load_file(scene_file)
        total = None
        for k in range(spp // chunk):
            img = mi.render(scene, spp=chunk, seed=seed + 2 * k)
            img = np.array(img, dtype=np.float64)[:, :, :3]
            total = img if total is None else total + img
        halves.append(total / (spp // chunk))
        if times is not None:
            times.append(time.perf_counter() - start)
    a, b = halves
    ratio = a.reshape(-1, 3).mean(axis=0) / b.reshape(-1, 3).mean(axis=0)
    return a, b, ratio
