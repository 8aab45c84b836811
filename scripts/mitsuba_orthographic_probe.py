"""Mitsuba 3.9.1's orthographic sensor: the rays it samples at film positions, for
tests/mitsuba.rs (`orthographic_sensor_is_mitsubas`).

Run: python3 scripts/mitsuba_orthographic_probe.py (pip mitsuba==3.9.1). Prints, for the
sensor below (the suite's orthographic_sensor scene with a 200 x 120 film), the ray origin and
direction at each film position (u, v) in [0, 1]^2, (0, 0) the top-left corner.
"""
import mitsuba as mi

mi.set_variant("scalar_rgb")
sensor = mi.load_string("""
<sensor type="orthographic" version="3.0.0">
    <float name="near_clip" value="1"/>
    <float name="far_clip" value="1000"/>
    <transform name="to_world">
        <scale x="1.5" y="1.5"/>
        <lookat target="0, 0, 1" origin="-5, 0, 3" up="0, 0, 1"/>
    </transform>
    <film type="hdrfilm">
        <rfilter type="box"/>
        <integer name="width" value="200"/>
        <integer name="height" value="120"/>
    </film>
</sensor>
""")
for u, v in [(0.0, 0.0), (1.0, 1.0), (0.25, 0.75), (0.5, 0.5)]:
    ray, _ = sensor.sample_ray(0.0, 0.5, [u, v], [0.5, 0.5])
    o, d = ray.o, ray.d
    print(f"({u}, {v}): o = ({o[0]:.6f}, {o[1]:.6f}, {o[2]:.6f}), "
          f"d = ({d[0]:.6f}, {d[1]:.6f}, {d[2]:.6f}), maxt = {ray.maxt:.3f}")
