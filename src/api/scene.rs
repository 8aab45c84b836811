//! [`Scene`]: a loaded scene, shared by the renderers opened on it.

use crate::api::{Backend, Renderer, Stop};
use crate::error::Result;
use crate::render::film::Image;
use crate::settings::RenderSettings;
use crate::warning::{collect, Warning};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// How [`Scene::load_with`] reads a scene, beyond the file itself (the command line's
/// `--camera`, `--define`, `--env` and `--env-scale`).
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// The glTF camera to render from, by name (default: the scene's first).
    pub camera: Option<String>,
    /// Mitsuba parameters `(NAME, VALUE)` for `$NAME`, overriding the file's `<default>`s.
    pub defines: Vec<(String, String)>,
    /// The environment light, supplied or replaced: `R,G,B` or a lat-long image file.
    pub env: Option<String>,
    /// Factor on `env`'s radiance or image.
    pub env_scale: Option<f32>,
}

impl LoadOptions {
    /// Parses a `NAME=VALUE` define (the command line's `-D`).
    pub fn parse_define(arg: &str) -> std::result::Result<(String, String), String> {
        crate::importers::mitsuba::parse_define(arg)
    }
}

/// A loaded scene: geometry, materials, lights, camera and the render settings its file
/// gives. Cloning is cheap (the scene is shared), and every [`Renderer`] opened on it keeps
/// it alive.
#[derive(Clone, Debug)]
pub struct Scene {
    inner: Arc<crate::scene::Scene>,
    path: PathBuf,
    warnings: Vec<Warning>,
}

impl Scene {
    /// Loads a scene by its extension: `.toml` (this renderer's format), `.xml` (Mitsuba 3)
    /// or `.gltf`/`.glb` (glTF 2.0). Errors name `FILE:LINE: field`. A scene with no light
    /// is an error.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene> {
        Scene::load_with(path, &LoadOptions::default())
    }

    /// [`Scene::load`] with a camera, Mitsuba parameters or an environment light.
    pub fn load_with(path: impl AsRef<Path>, options: &LoadOptions) -> Result<Scene> {
        let path = path.as_ref();
        let (scene, warnings) = collect(|| -> Result<crate::scene::Scene> {
            let camera = options.camera.as_deref();
            let mut scene = crate::importers::load_with_options(path, camera, &options.defines)?;
            let env = options.env.as_deref();
            crate::lights::environment::setup::apply_env_arg(
                &mut scene,
                env,
                options.env_scale,
                path,
            )?;
            Ok(scene)
        });
        Ok(Scene {
            inner: Arc::new(scene?),
            path: path.to_path_buf(),
            warnings,
        })
    }

    /// A scene built in memory ([`super::SceneBuild`]), `path` naming it.
    pub(super) fn built(scene: crate::scene::Scene, path: PathBuf) -> Scene {
        Scene {
            inner: Arc::new(scene),
            path,
            warnings: Vec::new(),
        }
    }

    /// The file the scene was read from (a built scene's name).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The render settings the scene file gives (defaults where it gives none).
    pub fn settings(&self) -> RenderSettings {
        self.inner.settings.clone()
    }

    /// What loading approximated or skipped (e.g. a glTF primitive that is not triangles).
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// The shared scene description, for a renderer's worker.
    pub(crate) fn shared(&self) -> Arc<crate::scene::Scene> {
        self.inner.clone()
    }

    /// The feature images `which` (albedo, normal) of the scene at `settings`' size, camera
    /// and seed, for denoisers: `samples` stratified first-hit samples per pixel, on the CPU,
    /// as Cycles defines its denoising passes (see [`crate::Aov`]).
    pub fn aovs(
        &self,
        settings: &RenderSettings,
        which: &[crate::Aov],
        samples: u32,
    ) -> Result<Vec<Image>> {
        crate::settings::validate(settings)?;
        Ok(crate::integrators::aov::render(
            &self.inner,
            settings,
            which,
            samples,
        ))
    }

    /// Renders the scene with `settings` on `backend`, as `gpu-photon render` does: the
    /// mean of progressive passes `0..settings.passes`, or one classic pass when `passes`
    /// is 0. Returns the image and the warnings of the render.
    pub fn render(
        &self,
        settings: &RenderSettings,
        backend: Backend,
    ) -> Result<(Image, Vec<Warning>)> {
        let mut r = Renderer::new(self, settings, backend)?;
        r.run(&Stop::default(), |_, _| {
            crate::render::progressive::Flow::Continue
        })?;
        Ok((r.image(), r.take_warnings()))
    }
}

/// The scene description itself, for the inner modules (`bench` reads it).
impl std::ops::Deref for Scene {
    type Target = crate::scene::Scene;
    fn deref(&self) -> &crate::scene::Scene {
        &self.inner
    }
}
