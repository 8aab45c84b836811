"""What the reference scripts share: Mitsuba renders in two independent halves and the
16 x 16-block RMSE they report. Imported by envlight_reference.py, filter_reference.py and
cornell_spectra.py (run them from anywhere: they put this directory on the path)."""
import numpy as np
import mitsuba as mi


def block_rmse(a, b, n=16):
    """RMSE of the n x n block means of the channel-mean difference of images a and b."""
    h, w, _ = a.shape
    d = (a - b).mean(axis=2)
    blocks = d[: h // n * n, : w // n * n].reshape(h // n, n, w // n, n).mean(axis=(1, 3))
    return float(np.sqrt((blocks ** 2).mean()))


def render_halves(scene_file, spp):
    """Two renders of scene_file at spp samples per pixel with seeds 1 and 2 (in the variant
    already set), as float64 (h, w, 3) arrays, and the mean per channel of their ratio."""
    halves = []
    for seed in (1, 2):
        img = mi.render(mi.load_file(scene_file), spp=spp, seed=seed)
        halves.append(np.array(img, dtype=np.float64)[:, :, :3])
    a, b = halves
    ratio = a.reshape(-1, 3).mean(axis=0) / b.reshape(-1, 3).mean(axis=0)
    return a, b, ratio
