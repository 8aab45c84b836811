//! `gpu_photon.SceneBuilder`: a scene built from NumPy arrays and dicts (`gpu_photon::SceneBuild`,
//! the same scene builder every importer feeds), for programs that hold a scene rather than a
//! file, such as the Blender add-on. Materials are dicts of the renderer's own kinds (see
//! `material`); errors are `SceneError`s naming the builder and the item.

use super::{to_py, PyScene};
use gpu_photon as gp;
use numpy::{PyReadonlyArray2, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyDictMethods};

/// A dict's values by key, remembering which were read so that the rest can be reported.
struct Fields<'py> {
    dict: &'py Bound<'py, PyDict>,
    read: Vec<&'static str>,
    item: String,
}

impl<'py> Fields<'py> {
    fn err(&self, key: &str, message: impl std::fmt::Display) -> PyErr {
        super::SceneError::new_err(format!("{}: {key}: {message}", self.item))
    }

    fn get<T: FromPyObjectOwned<'py>>(&mut self, key: &'static str) -> PyResult<Option<T>> {
        self.read.push(key);
        match self.dict.get_item(key)? {
            Some(v) if !v.is_none() => v.extract::<T>().map(Some).map_err(|e| {
                let e: PyErr = e.into();
                self.err(key, e)
            }),
            _ => Ok(None),
        }
    }

    fn or<T: FromPyObjectOwned<'py>>(&mut self, key: &'static str, default: T) -> PyResult<T> {
        Ok(self.get(key)?.unwrap_or(default))
    }

    /// Fails naming the keys that were not read.
    fn finish(self) -> PyResult<()> {
        for (k, _) in self.dict.iter() {
            let k: String = k.extract()?;
            if !self.read.contains(&k.as_str()) {
                let known = self.read.join(", ");
                return Err(self.err(&k, format!("unknown key (this kind reads {known})")));
            }
        }
        Ok(())
    }
}

/// The material a dict describes: `kind` (`black`, `diffuse`, `mirror`, `dielectric`,
/// `conductor`, `phong`, `metallic_roughness`, `transparent`) with that kind's parameters,
/// and for every kind `emission`, `two_sided_emission`, the textures and the alpha.
fn material(dict: &Bound<'_, PyDict>, name: &str) -> PyResult<gp::MaterialSpec> {
    let mut f = Fields {
        dict,
        read: Vec::new(),
        item: format!("materials[{name}]"),
    };
    let kind: String = f.get("kind")?.ok_or_else(|| f.err("kind", "missing"))?;
    let (white, black) = ([1.0f32; 3], [0.0f32; 3]);
    let scattering = match kind.as_str() {
        "black" => gp::Scattering::Black,
        "diffuse" => gp::Scattering::Diffuse {
            colour: f.or("colour", [0.8; 3])?,
        },
        "mirror" => gp::Scattering::Mirror {
            colour: f.or("colour", white)?,
        },
        "dielectric" => gp::Scattering::Dielectric {
            ior: f.or("ior", 1.5)?,
            roughness: f.or("roughness", 0.0)?,
            tint: f.or("tint", white)?,
        },
        "conductor" => gp::Scattering::Conductor {
            colour: f.or("colour", white)?,
            roughness: f.or("roughness", 0.0)?,
        },
        "phong" => gp::Scattering::Phong {
            kd: f.or("kd", black)?,
            ks: f.or("ks", black)?,
            exponent: f.or("exponent", 1.0)?,
        },
        "metallic_roughness" => gp::Scattering::MetallicRoughness {
            base: f.or("base", [0.8; 3])?,
            metallic: f.or("metallic", 0.0)?,
            roughness: f.or("roughness", 0.5)?,
            f0: f.or("f0", [0.04; 3])?,
            f90: f.or("f90", 1.0)?,
            transmission: f.or("transmission", 0.0)?,
        },
        "transparent" => gp::Scattering::Transparent,
        other => {
            let kinds = "black, diffuse, mirror, dielectric, conductor, phong, \
                         metallic_roughness, transparent";
            return Err(f.err("kind", format!("unknown kind `{other}` (expected {kinds})")));
        }
    };
    let mut spec = gp::MaterialSpec::new(scattering);
    spec.emission = f.or("emission", black)?;
    spec.two_sided_emission = f.or("two_sided_emission", false)?;
    spec.colour_texture = f.get("colour_texture")?;
    spec.metallic_roughness_texture = f.get("metallic_roughness_texture")?;
    spec.transmission_texture = f.get("transmission_texture")?;
    spec.normal_texture = f.get("normal_texture")?;
    spec.emission_texture = f.get("emission_texture")?;
    let alpha: Option<f32> = f.get("alpha")?;
    let alpha_texture: Option<u32> = f.get("alpha_texture")?;
    let cutoff: Option<f32> = f.get("alpha_cutoff")?;
    let luminance = f.or("alpha_luminance", false)?;
    if alpha.is_some() || alpha_texture.is_some() {
        spec.alpha = Some(gp::AlphaSpec {
            cutoff,
            factor: alpha.unwrap_or(1.0),
            texture: alpha_texture,
            luminance,
        });
    }
    f.finish()?;
    Ok(spec)
}

/// Rows of a (N, K) float32 array as fixed arrays, or the error naming `what`.
fn rows<const K: usize, T: numpy::Element + Copy + Default>(
    a: &PyReadonlyArray2<'_, T>,
    what: &str,
) -> PyResult<Vec<[T; K]>> {
    let shape = a.shape();
    if shape[1] != K {
        return Err(PyValueError::new_err(format!(
            "{what}: expected an array of shape (N, {K}), got {shape:?}"
        )));
    }
    let a = a.as_array();
    Ok(a.rows()
        .into_iter()
        .map(|r| std::array::from_fn(|i| r[i]))
        .collect())
}

/// A 4x4 row-major matrix as glam's columns.
fn matrix(t: &PyReadonlyArray2<'_, f32>) -> PyResult<[[f32; 4]; 4]> {
    let r = rows::<4, f32>(t, "transform")?;
    if r.len() != 4 {
        return Err(PyValueError::new_err("transform: expected a 4x4 matrix"));
    }
    Ok(std::array::from_fn(|c| std::array::from_fn(|i| r[i][c])))
}

/// A mesh's arrays, read from NumPy (shapes checked by `rows`).
struct MeshArrays {
    positions: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
    materials: Vec<u32>,
    normals: Option<Vec<[f32; 3]>>,
    uvs: Option<Vec<[f32; 2]>>,
    tangents: Option<Vec<[f32; 4]>>,
}

impl MeshArrays {
    fn read(
        positions: PyReadonlyArray2<'_, f32>,
        triangles: PyReadonlyArray2<'_, u32>,
        materials: numpy::PyReadonlyArray1<'_, u32>,
        normals: Option<PyReadonlyArray2<'_, f32>>,
        uvs: Option<PyReadonlyArray2<'_, f32>>,
        tangents: Option<PyReadonlyArray2<'_, f32>>,
    ) -> PyResult<Self> {
        Ok(MeshArrays {
            positions: rows::<3, f32>(&positions, "positions")?,
            triangles: rows::<3, u32>(&triangles, "triangles")?,
            materials: materials.as_array().iter().copied().collect(),
            normals: normals.map(|a| rows::<3, f32>(&a, "normals")).transpose()?,
            uvs: uvs.map(|a| rows::<2, f32>(&a, "uvs")).transpose()?,
            tangents: tangents
                .map(|a| rows::<4, f32>(&a, "tangents"))
                .transpose()?,
        })
    }

    fn spec(&self, transform: Option<[[f32; 4]; 4]>) -> gp::MeshSpec<'_> {
        gp::MeshSpec {
            positions: &self.positions,
            triangles: &self.triangles,
            materials: &self.materials,
            normals: self.normals.as_deref(),
            uvs: self.uvs.as_deref(),
            tangents: self.tangents.as_deref(),
            transform,
        }
    }
}

/// Builds a scene from arrays and dicts; `finish()` returns a `gpu_photon.Scene`.
#[pyclass(module = "gpu_photon", name = "SceneBuilder")]
pub struct PySceneBuilder {
    inner: Option<gp::SceneBuild>,
}

impl PySceneBuilder {
    fn b(&mut self) -> PyResult<&mut gp::SceneBuild> {
        self.inner
            .as_mut()
            .ok_or_else(|| super::Error::new_err("the builder has finished"))
    }
}

#[pymethods]
impl PySceneBuilder {
    /// An empty scene; `name` names it in errors.
    #[new]
    #[pyo3(signature = (name = "scene"))]
    fn new(name: &str) -> Self {
        PySceneBuilder {
            inner: Some(gp::SceneBuild::new(name)),
        }
    }

    /// Adds a texture from linear RGBA float32 texels (H, W, 4), row 0 at v = 0;
    /// `interpolation` "linear" or "closest", `extension` "repeat", "clamp" or "mirror".
    /// Returns its index for materials.
    #[pyo3(signature = (name, rgba, interpolation = "linear", extension = "repeat"))]
    fn add_texture(
        &mut self,
        py: Python<'_>,
        name: &str,
        rgba: PyReadonlyArray3<'_, f32>,
        interpolation: &str,
        extension: &str,
    ) -> PyResult<u32> {
        let shape = rgba.shape();
        if shape[2] != 4 {
            return Err(PyValueError::new_err(format!(
                "texture {name}: expected (H, W, 4) texels, got {shape:?}"
            )));
        }
        let wrap = match extension {
            "repeat" => gp::TextureWrap::Repeat,
            "clamp" => gp::TextureWrap::Clamp,
            "mirror" => gp::TextureWrap::Mirror,
            e => {
                return Err(PyValueError::new_err(format!(
                    "texture {name}: unknown extension {e}"
                )))
            }
        };
        let bilinear = match interpolation {
            "linear" => true,
            "closest" => false,
            i => {
                let m = format!("texture {name}: unknown interpolation {i}");
                return Err(PyValueError::new_err(m));
            }
        };
        let spec = gp::TextureSpec {
            name: name.to_string(),
            width: shape[1] as u32,
            height: shape[0] as u32,
            rgba: rgba.as_array().iter().copied().collect(),
            bilinear,
            wrap,
        };
        self.b()?.add_texture(spec).map_err(|e| to_py(py, e))
    }

    /// Adds a material described by a dict (`kind` and its parameters); returns its index.
    fn add_material(
        &mut self,
        py: Python<'_>,
        name: &str,
        spec: &Bound<'_, PyDict>,
    ) -> PyResult<u32> {
        let spec = material(spec, name)?;
        self.b()?
            .add_material(name, &spec)
            .map_err(|e| to_py(py, e))
    }

    /// Adds a mesh: positions (N, 3) float32, triangles (T, 3) uint32, materials (T,) or (1,)
    /// uint32, optional per-corner normals (3T, 3), uvs (3T, 2), tangents (3T, 4) and a 4x4
    /// object-to-world transform (row-major, as NumPy and Blender write matrices).
    #[pyo3(signature = (name, positions, triangles, materials, normals = None, uvs = None, tangents = None, transform = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_mesh(
        &mut self,
        py: Python<'_>,
        name: &str,
        positions: PyReadonlyArray2<'_, f32>,
        triangles: PyReadonlyArray2<'_, u32>,
        materials: numpy::PyReadonlyArray1<'_, u32>,
        normals: Option<PyReadonlyArray2<'_, f32>>,
        uvs: Option<PyReadonlyArray2<'_, f32>>,
        tangents: Option<PyReadonlyArray2<'_, f32>>,
        transform: Option<PyReadonlyArray2<'_, f32>>,
    ) -> PyResult<()> {
        let m = MeshArrays::read(positions, triangles, materials, normals, uvs, tangents)?;
        let transform = transform.map(|t| matrix(&t)).transpose()?;
        let b = self.b()?;
        py.detach(|| b.add_mesh(name, &m.spec(transform)))
            .map_err(|e| to_py(py, e))
    }

    /// Adds a mesh (the arrays of `add_mesh`, in its object space) as a group stored once;
    /// returns its index for `add_instance`. Its materials must pass `material_instanceable`.
    #[pyo3(signature = (name, positions, triangles, materials, normals = None, uvs = None, tangents = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_mesh_group(
        &mut self,
        py: Python<'_>,
        name: &str,
        positions: PyReadonlyArray2<'_, f32>,
        triangles: PyReadonlyArray2<'_, u32>,
        materials: numpy::PyReadonlyArray1<'_, u32>,
        normals: Option<PyReadonlyArray2<'_, f32>>,
        uvs: Option<PyReadonlyArray2<'_, f32>>,
        tangents: Option<PyReadonlyArray2<'_, f32>>,
    ) -> PyResult<u32> {
        let m = MeshArrays::read(positions, triangles, materials, normals, uvs, tangents)?;
        let b = self.b()?;
        py.detach(|| b.add_mesh_group(name, &m.spec(None)))
            .map_err(|e| to_py(py, e))
    }

    /// Places mesh group `group` by a 4x4 object-to-world `transform` (row-major); `name`
    /// names it in errors.
    fn add_instance(
        &mut self,
        py: Python<'_>,
        name: &str,
        group: u32,
        transform: PyReadonlyArray2<'_, f32>,
    ) -> PyResult<()> {
        let t = matrix(&transform)?;
        self.b()?
            .add_instance(name, group, t)
            .map_err(|e| to_py(py, e))
    }

    /// Whether material `material` may be in a mesh group (it neither emits nor is
    /// alpha-tested).
    fn material_instanceable(&mut self, material: u32) -> PyResult<bool> {
        Ok(self.b()?.material_instanceable(material))
    }

    /// Adds an analytic sphere of material `material`.
    fn add_sphere(
        &mut self,
        py: Python<'_>,
        name: &str,
        centre: [f32; 3],
        radius: f32,
        material: u32,
    ) -> PyResult<()> {
        let b = self.b()?;
        b.add_sphere(name, centre, radius, material)
            .map_err(|e| to_py(py, e))
    }

    /// Adds a point light, `intensity` in W/sr per channel.
    fn add_point_light(
        &mut self,
        py: Python<'_>,
        name: &str,
        position: [f32; 3],
        intensity: [f32; 3],
    ) -> PyResult<()> {
        let b = self.b()?;
        b.add_point_light(name, position, intensity)
            .map_err(|e| to_py(py, e))
    }

    /// Adds a spot light: `intensity` W/sr on its axis, half-angles `inner` and `outer` in
    /// degrees with glTF's falloff between.
    #[allow(clippy::too_many_arguments)]
    fn add_spot_light(
        &mut self,
        py: Python<'_>,
        name: &str,
        position: [f32; 3],
        direction: [f32; 3],
        intensity: [f32; 3],
        inner: f32,
        outer: f32,
    ) -> PyResult<()> {
        let b = self.b()?;
        b.add_spot_light(name, position, direction, intensity, inner, outer)
            .map_err(|e| to_py(py, e))
    }

    /// Adds a directional light travelling along `direction`, `irradiance` in W/m^2.
    fn add_directional_light(
        &mut self,
        py: Python<'_>,
        name: &str,
        direction: [f32; 3],
        irradiance: [f32; 3],
    ) -> PyResult<()> {
        let b = self.b()?;
        b.add_directional_light(name, direction, irradiance)
            .map_err(|e| to_py(py, e))
    }

    /// Sets the environment: `radiance`, times a lat-long float32 image (H, W, 3) (row 0 at
    /// the zenith, Mitsuba's `envmap` mapping) turned by `to_world` (3x3, row-major).
    #[pyo3(signature = (radiance, image = None, to_world = None))]
    fn set_environment(
        &mut self,
        py: Python<'_>,
        radiance: [f32; 3],
        image: Option<PyReadonlyArray3<'_, f32>>,
        to_world: Option<[[f32; 3]; 3]>,
    ) -> PyResult<()> {
        let image = match image {
            Some(a) => {
                let shape = a.shape();
                if shape[2] != 3 {
                    let m = format!("environment: expected (H, W, 3) texels, got {shape:?}");
                    return Err(PyValueError::new_err(m));
                }
                let data = a.as_array().iter().copied().collect();
                Some((shape[1] as u32, shape[0] as u32, data))
            }
            None => None,
        };
        let r = to_world.unwrap_or([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        let columns = std::array::from_fn(|c| std::array::from_fn(|i| r[i][c]));
        self.b()?
            .set_environment(radiance, image, columns)
            .map_err(|e| to_py(py, e))
    }

    /// Sets the camera (a pinhole, or a thin lens of `aperture_radius` focused at
    /// `focus_distance`; with `orthographic_height`, an orthographic camera whose view is that
    /// many scene units high) and the image size.
    #[pyo3(signature = (eye, forward, up, fov_y, width, height, aperture_radius = 0.0, focus_distance = 1.0, orthographic_height = None))]
    #[allow(clippy::too_many_arguments)]
    fn set_camera(
        &mut self,
        py: Python<'_>,
        eye: [f32; 3],
        forward: [f32; 3],
        up: [f32; 3],
        fov_y: f32,
        width: u32,
        height: u32,
        aperture_radius: f32,
        focus_distance: f32,
        orthographic_height: Option<f32>,
    ) -> PyResult<()> {
        let c = gp::CameraSpec {
            orthographic_height,
            eye,
            forward,
            up,
            fov_y,
            aperture_radius,
            focus_distance,
        };
        self.b()?
            .set_camera(&c, width, height)
            .map_err(|e| to_py(py, e))
    }

    /// The scene (the builder cannot be used after).
    fn finish(&mut self, py: Python<'_>) -> PyResult<PyScene> {
        let b = self
            .inner
            .take()
            .ok_or_else(|| super::Error::new_err("the builder has finished"))?;
        let scene = py.detach(|| b.finish()).map_err(|e| to_py(py, e))?;
        Ok(PyScene { scene })
    }
}
