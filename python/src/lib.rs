//! The native half of the `gpu_photon` Python package: the Rust facade (`gpu_photon::Scene`,
//! `Renderer`, `RenderSettings`, `Image`) as Python classes, images as float32 NumPy arrays
//! (H, W, 3), the library's errors as exceptions and its warnings through `warnings`.
//! Rendering runs with the interpreter released; a pass is never interrupted, so Ctrl-C
//! (KeyboardInterrupt) takes effect after the pass in progress.

use gpu_photon as gp;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyOSError, PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyDictMethods};
use std::ffi::CString;
use std::sync::Mutex;

mod build;

create_exception!(_gpu_photon, Error, PyException, "An error of gpu-photon.");
create_exception!(
    _gpu_photon,
    SceneError,
    Error,
    "A scene file is malformed: the message is `FILE:LINE: field: what`; the attributes \
     file, line, field and message hold its parts."
);
create_exception!(
    _gpu_photon,
    SettingError,
    Error,
    "A render setting is unknown or out of its range (the command line's names and ranges)."
);
create_exception!(
    _gpu_photon,
    GpuPhotonWarning,
    PyUserWarning,
    "Something a load or a render approximated, skipped or fell back from."
);

/// The library's error as a Python exception: scene errors carry their parts.
fn to_py(py: Python<'_>, e: gp::Error) -> PyErr {
    let text = e.to_string();
    match e {
        gp::Error::Scene {
            file,
            line,
            field,
            message,
        } => {
            let err = SceneError::new_err(text);
            let value = err.value(py);
            let _ = value.setattr("file", file);
            let _ = value.setattr("line", line);
            let _ = value.setattr("field", field);
            let _ = value.setattr("message", message);
            err
        }
        gp::Error::Setting { .. } | gp::Error::Sizes(_) => SettingError::new_err(text),
        gp::Error::Io { .. } => PyOSError::new_err(text),
        _ => Error::new_err(text),
    }
}

/// Issues each warning through Python's `warnings` module.
fn warn_all(py: Python<'_>, warnings: &[gp::Warning]) -> PyResult<()> {
    let category = py.get_type::<GpuPhotonWarning>();
    for w in warnings {
        let text = CString::new(w.message.replace('\0', " ")).unwrap_or_default();
        PyErr::warn(py, category.as_any(), &text, 2)?;
    }
    Ok(())
}

/// An image as a float32 array (H, W, 3), built on the image's own buffer (no copy).
fn to_array(py: Python<'_>, image: gp::Image) -> PyResult<Bound<'_, PyAny>> {
    let (w, h) = (image.width as usize, image.height as usize);
    let flat = PyArray1::from_vec(py, image.into_rgb());
    Ok(flat.reshape([h, w, 3])?.into_any())
}

/// A float32 array (H, W, 3) as an image.
fn from_array(py: Python<'_>, a: PyReadonlyArray3<'_, f32>) -> PyResult<gp::Image> {
    let shape = a.shape();
    if shape[2] != 3 {
        return Err(PyValueError::new_err(format!(
            "expected an array of shape (H, W, 3), got {shape:?}"
        )));
    }
    let rgb = a.as_array().iter().copied().collect();
    gp::Image::from_rgb(shape[1] as u32, shape[0] as u32, rgb).map_err(|e| to_py(py, e))
}

fn backend(name: &str) -> PyResult<gp::Backend> {
    match name {
        "auto" => Ok(gp::Backend::Auto),
        "cpu" => Ok(gp::Backend::Cpu),
        "gpu" => Ok(gp::Backend::Gpu),
        _ => Err(SettingError::new_err(format!(
            "invalid setting backend: {name}: expected one of auto, cpu, gpu"
        ))),
    }
}

/// `settings` with every keyword of `kwargs` applied by name (`None` values skipped).
fn apply(
    py: Python<'_>,
    mut settings: gp::RenderSettings,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<gp::RenderSettings> {
    for (key, value) in kwargs.into_iter().flat_map(|d| d.iter()) {
        let name: String = key.extract()?;
        if value.is_none() {
            continue;
        }
        let v = if value.is_instance_of::<pyo3::types::PyBool>() {
            return Err(SettingError::new_err(format!(
                "invalid setting {name}: expected a number or a name, not a bool"
            )));
        } else if let Ok(i) = value.extract::<i64>() {
            gp::SettingValue::Int(i)
        } else if let Ok(f) = value.extract::<f64>() {
            gp::SettingValue::Float(f)
        } else {
            gp::SettingValue::Text(value.extract::<String>()?)
        };
        settings.set(&name, v).map_err(|e| to_py(py, e))?;
    }
    Ok(settings)
}

/// A loaded scene (TOML, Mitsuba 3 XML or glTF).
#[pyclass(module = "gpu_photon", name = "Scene", frozen)]
struct PyScene {
    scene: gp::Scene,
}

#[pymethods]
impl PyScene {
    /// The file the scene was read from.
    #[getter]
    fn path(&self) -> String {
        self.scene.path().display().to_string()
    }

    /// The scene's own render settings, by name (the command line's names).
    fn settings(&self) -> std::collections::BTreeMap<&'static str, f64> {
        let s = self.scene.settings();
        gp::RenderSettings::names()
            .into_iter()
            .filter_map(|n| s.get(n).map(|v| (n, v)))
            .collect()
    }

    /// The mean of the progressive passes `0..passes` (one classic pass when passes=0) as a
    /// float32 array (H, W, 3); settings by keyword, as the command line's flags with `_`.
    #[pyo3(signature = (backend = "auto", **settings))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        backend: &str,
        settings: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mut r = PyRenderer::open(py, &self.scene, backend, settings)?;
        r.run_passes(py, None, None, None)?;
        to_array(py, r.inner.get_mut().map_err(poisoned)?.image())
    }

    /// Feature images for denoisers (`albedo`, `normal`: Cycles' Denoising Albedo and
    /// Denoising Normal, the normal in camera space) at the settings' size, camera and seed,
    /// `samples` first-hit samples per pixel on the CPU; a dict of float32 arrays (H, W, 3).
    #[pyo3(signature = (names = vec!["albedo".to_string(), "normal".to_string()], samples = 4, **settings))]
    fn aovs<'py>(
        &self,
        py: Python<'py>,
        names: Vec<String>,
        samples: u32,
        settings: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let which = gp::Aov::parse_list(&names.join(",")).map_err(|e| to_py(py, e))?;
        let settings = apply(py, self.scene.settings(), settings)?;
        let images = py
            .detach(|| self.scene.aovs(&settings, &which, samples))
            .map_err(|e| to_py(py, e))?;
        let d = PyDict::new(py);
        for (aov, image) in which.iter().zip(images) {
            d.set_item(aov.name(), to_array(py, image)?)?;
        }
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!("gpu_photon.Scene({:?})", self.scene.path())
    }
}

fn poisoned<T>(_: T) -> PyErr {
    Error::new_err("the renderer failed earlier (poisoned)")
}

/// Loads a scene by its extension: .toml, .xml (Mitsuba 3) or .gltf/.glb.
#[pyfunction]
#[pyo3(signature = (path, camera = None, defines = None, env = None, env_scale = None))]
fn load(
    py: Python<'_>,
    path: std::path::PathBuf,
    camera: Option<String>,
    defines: Option<std::collections::BTreeMap<String, String>>,
    env: Option<String>,
    env_scale: Option<f32>,
) -> PyResult<PyScene> {
    let options = gp::LoadOptions {
        camera,
        defines: defines.unwrap_or_default().into_iter().collect(),
        env,
        env_scale,
    };
    let scene = py
        .detach(|| gp::Scene::load_with(&path, &options))
        .map_err(|e| to_py(py, e))?;
    warn_all(py, scene.warnings())?;
    Ok(PyScene { scene })
}

/// A renderer opened once on a scene, rendering pass after pass into a running mean.
#[pyclass(module = "gpu_photon", name = "Renderer")]
struct PyRenderer {
    inner: Mutex<gp::Renderer>,
    /// The scene file, the settings and the `passes` keyword, for [`PyRenderer::write`]'s
    /// tags (what `gpu-photon render` writes for the same file and flags).
    scene_path: std::path::PathBuf,
    settings: gp::RenderSettings,
    total: Option<u32>,
}

impl PyRenderer {
    fn open(
        py: Python<'_>,
        scene: &gp::Scene,
        backend_name: &str,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<PyRenderer> {
        let total = match settings
            .map(|d| d.get_item("passes"))
            .transpose()?
            .flatten()
        {
            Some(v) => Some(v.extract::<u32>()?),
            None => None,
        };
        let settings = apply(py, scene.settings(), settings)?;
        let b = backend(backend_name)?;
        let mut r = py
            .detach(|| gp::Renderer::new(scene, &settings, b))
            .map_err(|e| to_py(py, e))?;
        warn_all(py, &r.take_warnings())?;
        Ok(PyRenderer {
            inner: Mutex::new(r),
            scene_path: scene.path().to_path_buf(),
            settings,
            total,
        })
    }

    /// Renders passes until the plan, `time`, `noise`, `callback` returning False, or a
    /// KeyboardInterrupt (raised after the pass) stops them.
    fn run_passes(
        &mut self,
        py: Python<'_>,
        callback: Option<&Bound<'_, PyAny>>,
        time: Option<f64>,
        noise: Option<f64>,
    ) -> PyResult<u32> {
        let r = self.inner.get_mut().map_err(poisoned)?;
        let mut rendered = 0;
        loop {
            let more = py.detach(|| r.render_pass()).map_err(|e| to_py(py, e))?;
            warn_all(py, &r.take_warnings())?;
            if !more {
                return Ok(rendered);
            }
            rendered += 1;
            let elapsed = r.elapsed().as_secs_f64();
            if let Some(f) = callback {
                let info = PyDict::new(py);
                info.set_item("pass", r.done().end - 1)?;
                info.set_item("done", r.done().len())?;
                info.set_item("noise", r.noise())?;
                info.set_item("elapsed", elapsed)?;
                info.set_item("image", to_array(py, r.image())?)?;
                let answer = f.call1((info,))?;
                if !answer.is_none() && !answer.is_truthy()? {
                    return Ok(rendered);
                }
            }
            py.check_signals()?;
            let quiet = noise.zip(r.noise()).is_some_and(|(t, n)| n <= t);
            if time.is_some_and(|t| elapsed >= t) || quiet {
                return Ok(rendered);
            }
        }
    }
}

#[pymethods]
impl PyRenderer {
    /// Opens `backend` ("auto", "cpu" or "gpu") on `scene` with its settings changed by
    /// keyword; `passes=0` renders one classic pass.
    #[new]
    #[pyo3(signature = (scene, backend = "auto", **settings))]
    fn new(
        py: Python<'_>,
        scene: &Bound<'_, PyScene>,
        backend: &str,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<PyRenderer> {
        PyRenderer::open(py, &scene.get().scene, backend, settings)
    }

    /// Renders the planned passes (or until `time` seconds or a relative `noise` target),
    /// calling `callback(info)` after each with a dict (pass, done, noise, elapsed, image);
    /// a callback returning False stops. Returns the passes rendered by this call.
    #[pyo3(signature = (callback = None, time = None, noise = None))]
    fn run(
        &mut self,
        py: Python<'_>,
        callback: Option<&Bound<'_, PyAny>>,
        time: Option<f64>,
        noise: Option<f64>,
    ) -> PyResult<u32> {
        self.run_passes(py, callback, time, noise)
    }

    /// Renders the next pass; False when the planned passes are done.
    fn render_pass(&mut self, py: Python<'_>) -> PyResult<bool> {
        let r = self.inner.get_mut().map_err(poisoned)?;
        let more = py.detach(|| r.render_pass()).map_err(|e| to_py(py, e))?;
        warn_all(py, &r.take_warnings())?;
        Ok(more)
    }

    /// The mean of the passes so far, float32 (H, W, 3).
    fn image<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_array(py, self.inner.get_mut().map_err(poisoned)?.image())
    }

    /// Writes the mean of the passes so far to `path` (EXR or PNG, atomically) as
    /// `gpu-photon render` writes it: tagged with its passes and a fingerprint of the scene
    /// file and settings, so `gpu-photon merge` takes it; the same bytes as the command's
    /// file for the same scene and settings.
    fn write(&mut self, py: Python<'_>, path: std::path::PathBuf) -> PyResult<()> {
        let r = self.inner.get_mut().map_err(poisoned)?;
        let file = gp::SliceFile::new(&self.scene_path, &path, &self.settings, self.total)
            .map_err(|e| to_py(py, e))?;
        file.write(r).map_err(|e| to_py(py, e))
    }

    /// The passes in the mean, as (first, end).
    #[getter]
    fn done(&mut self) -> PyResult<(u32, u32)> {
        let d = self.inner.get_mut().map_err(poisoned)?.done();
        Ok((d.start, d.end))
    }

    /// The estimated relative noise of the mean (after an even number of passes), or None.
    #[getter]
    fn noise(&mut self) -> PyResult<Option<f64>> {
        Ok(self.inner.get_mut().map_err(poisoned)?.noise())
    }

    /// Which backend ran, and seconds per phase.
    fn report<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let r = self.inner.get_mut().map_err(poisoned)?;
        let report = r.report().map_err(|e| to_py(py, e))?;
        let d = PyDict::new(py);
        d.set_item("backend", &report.backend)?;
        let phases = PyDict::new(py);
        for (name, t) in &report.phases {
            let before: f64 = phases.get_item(name)?.map_or(Ok(0.0), |v| v.extract())?;
            phases.set_item(name, before + t.as_secs_f64())?;
        }
        d.set_item("phases", phases)?;
        Ok(d)
    }
}

/// `gpu-photon diff`'s statistics of `a` against the reference `b` (float32 arrays).
#[pyfunction]
#[pyo3(signature = (a, b, block = 16))]
fn diff<'py>(
    py: Python<'py>,
    a: PyReadonlyArray3<'_, f32>,
    b: PyReadonlyArray3<'_, f32>,
    block: u32,
) -> PyResult<Bound<'py, PyDict>> {
    let (a, b) = (from_array(py, a)?, from_array(py, b)?);
    let s = a.diff(&b, block).map_err(|e| to_py(py, e))?;
    let d = PyDict::new(py);
    d.set_item("rmse", s.rmse)?;
    d.set_item("block_rmse", s.block_rmse)?;
    d.set_item("rel_mse", s.rel_mse)?;
    d.set_item("mean_ratio", s.mean_ratio.to_vec())?;
    d.set_item("max_error", s.max_error)?;
    d.set_item("lines", s.lines(block))?;
    Ok(d)
}

/// Writes a linear float EXR.
#[pyfunction]
fn write_exr(
    py: Python<'_>,
    path: std::path::PathBuf,
    image: PyReadonlyArray3<'_, f32>,
) -> PyResult<()> {
    let image = from_array(py, image)?;
    image.write_exr(&path).map_err(|e| to_py(py, e))
}

/// Writes an 8-bit sRGB PNG scaled by 2**exposure.
#[pyfunction]
#[pyo3(signature = (path, image, exposure = 0.0))]
fn write_png(
    py: Python<'_>,
    path: std::path::PathBuf,
    image: PyReadonlyArray3<'_, f32>,
    exposure: f32,
) -> PyResult<()> {
    let image = from_array(py, image)?;
    image.write_png(&path, exposure).map_err(|e| to_py(py, e))
}

/// Reads an EXR (linear) or PNG (sRGB, decoded to linear) as float32 (H, W, 3).
#[pyfunction]
fn read_image(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Bound<'_, PyAny>> {
    let image = gp::Image::read(&path).map_err(|e| to_py(py, e))?;
    to_array(py, image)
}

/// The module `gpu_photon._gpu_photon`.
#[pymodule]
fn _gpu_photon(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    gp::quiet_headless_vulkan();
    m.add_class::<PyScene>()?;
    m.add_class::<PyRenderer>()?;
    m.add_class::<build::PySceneBuilder>()?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(diff, m)?)?;
    m.add_function(wrap_pyfunction!(write_exr, m)?)?;
    m.add_function(wrap_pyfunction!(write_png, m)?)?;
    m.add_function(wrap_pyfunction!(read_image, m)?)?;
    m.add("Error", py.get_type::<Error>())?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("SettingError", py.get_type::<SettingError>())?;
    m.add("GpuPhotonWarning", py.get_type::<GpuPhotonWarning>())?;
    m.add("setting_names", gp::RenderSettings::names())?;
    Ok(())
}
