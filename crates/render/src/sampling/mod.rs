//! Sampling formulas below every layer that samples: the warps from the unit
//! square to disks, hemispheres and spheres ([`warps`]: shapes, lights and
//! BSDFs sample with them) and the multiple importance sampling heuristics
//! ([`MisHeuristic`]: integrators and layered BSDFs weigh strategies with
//! them). A leaf module: it imports nothing of the renderer. (The
//! samplers that produce the numbers are [`crate::sampler`].)

mod mis;
pub mod warps;

pub use mis::MisHeuristic;
pub use warps::{
    UNIFORM_SPHERE_PDF, cosine_hemisphere_pdf, sample_cosine_hemisphere,
    sample_uniform_disk_concentric, sample_uniform_disk_concentric_trigonometric,
    sample_uniform_sphere,
};
