//! Checks a glTF file's raw JSON before the `gltf` crate reads it. The crate panics in its own
//! validation on a `POSITION` accessor that does not exist, unwraps a camera's parameters
//! for its `type` and an image's source, and takes an index modulo 2^32 (`4294967297` would
//! mean 1). So every index (of scenes, nodes, cameras, meshes, skins, accessors, bufferViews,
//! buffers, images, textures, samplers, materials and punctual lights) is checked here
//! against the length of the array it points into, each camera against its type and each
//! image for its source. Problems are (field path, message) for the caller to locate.

use serde_json::{Map, Value};

type Problem = (String, String);

/// Checks `json`, the parsed text of a glTF file. A root that is not an object passes: the
/// `gltf` crate reports it.
pub(crate) fn check(json: &Value) -> Result<(), Problem> {
    let Some(root) = json.as_object() else {
        return Ok(());
    };
    let c = Refs { root };
    c.one("scene", root.get("scene"), "scenes")?;
    for (i, scene) in c.items("scenes") {
        c.list(&format!("scenes[{i}].nodes"), scene.get("nodes"), "nodes")?;
    }
    for (i, node) in c.items("nodes") {
        let f = format!("nodes[{i}]");
        c.list(&format!("{f}.children"), node.get("children"), "nodes")?;
        c.one(&format!("{f}.camera"), node.get("camera"), "cameras")?;
        c.one(&format!("{f}.mesh"), node.get("mesh"), "meshes")?;
        c.one(&format!("{f}.skin"), node.get("skin"), "skins")?;
        let light = member(node, &["extensions", "KHR_lights_punctual", "light"]);
        let field = format!("{f}.extensions.KHR_lights_punctual.light");
        c.one(&field, light, "extensions.KHR_lights_punctual.lights")?;
    }
    for (i, mesh) in c.items("meshes") {
        for (j, p) in objects(mesh.get("primitives")) {
            let f = format!("meshes[{i}].primitives[{j}]");
            let attributes = p.get("attributes").and_then(Value::as_object);
            c.map(&format!("{f}.attributes"), attributes)?;
            c.one(&format!("{f}.indices"), p.get("indices"), "accessors")?;
            c.one(&format!("{f}.material"), p.get("material"), "materials")?;
            for (k, target) in objects(p.get("targets")) {
                c.map(&format!("{f}.targets[{k}]"), Some(target))?;
            }
        }
    }
    for (i, accessor) in c.items("accessors") {
        let f = format!("accessors[{i}]");
        c.one(
            &format!("{f}.bufferView"),
            accessor.get("bufferView"),
            "bufferViews",
        )?;
        for part in ["indices", "values"] {
            let view = member(accessor, &["sparse", part, "bufferView"]);
            c.one(
                &format!("{f}.sparse.{part}.bufferView"),
                view,
                "bufferViews",
            )?;
        }
    }
    for (i, view) in c.items("bufferViews") {
        c.one(
            &format!("bufferViews[{i}].buffer"),
            view.get("buffer"),
            "buffers",
        )?;
    }
    for (i, image) in c.items("images") {
        let field = format!("images[{i}].bufferView");
        c.one(&field, image.get("bufferView"), "bufferViews")?;
        image_source(i, image)?;
    }
    for (i, texture) in c.items("textures") {
        c.one(
            &format!("textures[{i}].source"),
            texture.get("source"),
            "images",
        )?;
        c.one(
            &format!("textures[{i}].sampler"),
            texture.get("sampler"),
            "samplers",
        )?;
    }
    for (i, material) in c.items("materials") {
        c.texture_refs(&format!("materials[{i}]"), material)?;
    }
    for (i, skin) in c.items("skins") {
        let f = format!("skins[{i}]");
        c.list(&format!("{f}.joints"), skin.get("joints"), "nodes")?;
        c.one(&format!("{f}.skeleton"), skin.get("skeleton"), "nodes")?;
        let matrices = skin.get("inverseBindMatrices");
        c.one(&format!("{f}.inverseBindMatrices"), matrices, "accessors")?;
    }
    for (i, animation) in c.items("animations") {
        animation_refs(&c, i, animation)?;
    }
    for (i, camera) in c.items("cameras") {
        camera_type(i, camera)?;
    }
    Ok(())
}

/// The channels and samplers of `animations[i]`.
fn animation_refs(c: &Refs, i: usize, animation: &Map<String, Value>) -> Result<(), Problem> {
    let f = format!("animations[{i}]");
    let samplers = animation.get("samplers").and_then(Value::as_array);
    for (j, channel) in objects(animation.get("channels")) {
        let field = format!("{f}.channels[{j}].sampler");
        let len = samplers.map_or(0, Vec::len);
        index_in(&field, channel.get("sampler"), "samplers", len)?;
        let node = member(channel, &["target", "node"]);
        c.one(&format!("{f}.channels[{j}].target.node"), node, "nodes")?;
    }
    for (j, sampler) in objects(animation.get("samplers")) {
        for end in ["input", "output"] {
            let field = format!("{f}.samplers[{j}].{end}");
            c.one(&field, sampler.get(end), "accessors")?;
        }
    }
    Ok(())
}

/// An image needs a `uri` or a `bufferView`, and with a `bufferView` a `mimeType` (the crate
/// unwraps them).
fn image_source(i: usize, image: &Map<String, Value>) -> Result<(), Problem> {
    let has = |key: &str| image.contains_key(key);
    match (has("bufferView"), has("uri"), has("mimeType")) {
        (true, _, false) => Err((
            format!("images[{i}].bufferView"),
            "an image in a bufferView needs a `mimeType`".into(),
        )),
        (false, false, _) => Err((
            format!("images[{i}]"),
            "an image needs a `uri` or a `bufferView`".into(),
        )),
        _ => Ok(()),
    }
}

/// A camera's `type` must come with its parameters object (the crate unwraps it); other
/// types, and a missing one, are left to the crate's validation.
fn camera_type(i: usize, camera: &Map<String, Value>) -> Result<(), Problem> {
    match camera.get("type").and_then(Value::as_str) {
        Some(kind @ ("perspective" | "orthographic")) if !camera.contains_key(kind) => Err((
            format!("cameras[{i}].type"),
            format!("type `{kind}` has no `{kind}` object"),
        )),
        _ => Ok(()),
    }
}

/// The root object, whose arrays indices point into.
struct Refs<'a> {
    root: &'a Map<String, Value>,
}

impl Refs<'_> {
    /// The objects of the root array `name` (a dotted path for an extension's array).
    fn items(&self, name: &str) -> impl Iterator<Item = (usize, &Map<String, Value>)> {
        objects(self.array(name))
    }

    fn array(&self, name: &str) -> Option<&Value> {
        let path: Vec<&str> = name.split('.').collect();
        member(self.root, &path)
    }

    /// `value` (if present) must index the root array `array`.
    fn one(&self, field: &str, value: Option<&Value>, array: &str) -> Result<(), Problem> {
        let len = self
            .array(array)
            .and_then(Value::as_array)
            .map_or(0, Vec::len);
        let name = array.rsplit('.').next().unwrap_or(array);
        index_in(field, value, name, len)
    }

    /// Every element of the list `value` (if present) must index `array`.
    fn list(&self, field: &str, value: Option<&Value>, array: &str) -> Result<(), Problem> {
        let items = value
            .and_then(Value::as_array)
            .map_or(&[][..], Vec::as_slice);
        for (i, v) in items.iter().enumerate() {
            self.one(&format!("{field}[{i}]"), Some(v), array)?;
        }
        Ok(())
    }

    /// Every member of the object `value` (attributes, morph targets) must index an accessor.
    fn map(&self, field: &str, value: Option<&Map<String, Value>>) -> Result<(), Problem> {
        for (name, v) in value.into_iter().flatten() {
            self.one(&format!("{field}.{name}"), Some(v), "accessors")?;
        }
        Ok(())
    }

    /// Every `...Texture` object inside a material (core and extensions) must index a
    /// texture.
    fn texture_refs(&self, field: &str, object: &Map<String, Value>) -> Result<(), Problem> {
        for (key, value) in object {
            let Some(inner) = value.as_object() else {
                continue;
            };
            let f = format!("{field}.{key}");
            if key.ends_with("Texture") {
                self.one(&format!("{f}.index"), inner.get("index"), "textures")?;
            }
            self.texture_refs(&f, inner)?;
        }
        Ok(())
    }
}

/// `value` (if present) must be an index below `len` into the array `plural`.
fn index_in(field: &str, value: Option<&Value>, plural: &str, len: usize) -> Result<(), Problem> {
    let Some(value) = value else {
        return Ok(());
    };
    let fail = |m: String| Err((field.to_string(), m));
    let Some(i) = value.as_u64() else {
        return fail(format!("must be an index (an integer >= 0), not {value}"));
    };
    if i < len as u64 {
        return Ok(());
    }
    let one = match plural {
        "meshes" => "mesh",
        p => p.strip_suffix('s').unwrap_or(p),
    };
    let count = if len == 1 { one } else { plural };
    fail(format!("{one} {i} does not exist ({len} {count})"))
}

/// The member at `path` inside `object`.
fn member<'v>(object: &'v Map<String, Value>, path: &[&str]) -> Option<&'v Value> {
    let (first, rest) = path.split_first()?;
    let value = object.get(*first)?;
    match rest {
        [] => Some(value),
        _ => member(value.as_object()?, rest),
    }
}

/// The objects of the array `value`, with their positions (other elements are skipped).
fn objects(value: Option<&Value>) -> impl Iterator<Item = (usize, &Map<String, Value>)> {
    let items = value
        .and_then(Value::as_array)
        .map_or(&[][..], Vec::as_slice);
    items
        .iter()
        .enumerate()
        .filter_map(|(i, v)| Some((i, v.as_object()?)))
}
