// gather_ray: a final-gather ray (gather.wgsl's camera paths trace one at each shaded hit and
// at a medium's near gather) through mirrors, glass and media to the radiance cache
// (radiance_cache.wgsl), twin of src/integrators/cpu/final_gather.rs. Library of the gather
// kernel; writes nothing.

// Where a camera path's gather ray starts (gather_ray's arguments) and what its light is
// weighed by.
struct GatherStart {
    x: vec3<f32>,
    n: vec3<f32>,
    dir: vec3<f32>,
    depth: u32,
    medium: u32,
    w: vec3<f32>,
}

// A final-gather ray from a hit at x (geometric normal n, camera depth `depth`) along dir:
// through mirrors (times ks) and glass (one Fresnel-chosen branch, one rng draw), depth + 1
// per bounce up to max_depth, to its first shaded hit y, where it adds throughput *
// the diffuse albedo of y * the radiance cache at y (normal facing the ray). Where y has a lobe
// it goes on along it. It never counts emission (shadow rays and caustic photons carry it).
// Through media (it starts in `medium_in`) every segment adds the volume map's whole
// in-scattered light (follow_chain) and carries its transmittance.
fn gather_ray(x: vec3<f32>, n: vec3<f32>, dir: vec3<f32>, depth: u32, medium_in: u32, rng: ptr<function, Rng>) -> vec3<f32> {
    var medium = medium_in;
    var d = dir;
    var o = offset_origin(x, n, d);
    var t = vec3<f32>(1.0);
    var sum = vec3<f32>(0.0);
    var gd = depth + 1u;
    loop {
        // No emission: light from a light directly (shadow rays) or over delta and glossy
        // lobes (L (S|G)+ D: the caustic map) is counted elsewhere.
        // (Bounded: follow_chain spends a loop step per ray, and shades nothing once refused.)
        let end = follow_chain(&o, &d, &t, &gd, &medium, false, rng, 0.0, vec3<f32>(0.0), vec3<f32>(0.0));
        sum += end.emitted;
        if !end.shade {
            break;
        }
        let hit = end.hit;
        let m = end.m;
        let can_continue = gd < params.max_depth;
        let lf = facing(hit, dot(-d, hit.normal) >= 0.0);
        sum += t * surface_diffuse_albedo(m, -d) * cache_lookup(hit.position, lf.ng);
        // A lobe is not in the cache (Lambertian radiance): go on along one direction drawn
        // from the lobe, weighted as the camera's lobe ray is.
        if !surface_has_lobe(m) || !can_continue {
            break;
        }
        let lr = surface_sample_lobe(m, d, lf, rng);
        if !lr.ok {
            break;
        }
        t *= lr.weight;
        d = lr.dir;
        if HAS_MEDIA {
            medium = medium_after(hit, medium, d);
        }
        o = offset_origin(hit.position, hit.normal, d);
        gd += 1u;
    }
    return sum;
}
