//! Light tracing (placeholder while the path-space core is built).

use super::path::PathSettings;
use super::{Integrator, IntegratorRender, RenderError, RunControl};
use crate::scene::Scene;

/// Light tracing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightIntegrator {
    settings: PathSettings,
}

impl LightIntegrator {
    /// Light tracing with `settings`.
    pub fn new(settings: PathSettings) -> Self {
        Self { settings }
    }
}

impl Integrator for LightIntegrator {
    fn render(
        &self,
        _scene: &Scene,
        _run: &RunControl<'_>,
    ) -> Result<IntegratorRender, RenderError> {
        let _ = self.settings;
        Err(RenderError::Unsupported(
            "light tracing is not built yet".into(),
        ))
    }
}
