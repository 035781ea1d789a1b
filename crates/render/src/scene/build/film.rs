//! The film's pixel reconstruction filter from the scene description's
//! [`FilterDescription`] (the camera is made by
//! [`crate::camera::PerspectiveCamera::new`] from its settings directly).

use super::parameter_error;
use crate::film::{BoxFilter, Filter, GaussianFilter, TriangleFilter};
use crate::scene::SceneError;
use crate::scene::description::FilterDescription;

/// The filter `description` stands for, its radius and width checked.
pub(in crate::scene) fn filter(description: &FilterDescription) -> Result<Filter, SceneError> {
    match *description {
        FilterDescription::Box { radius } => BoxFilter::new([radius; 2]).map(Filter::Box),
        FilterDescription::Tent { radius } => {
            TriangleFilter::new([radius; 2]).map(Filter::Triangle)
        }
        FilterDescription::Gaussian { radius, sigma } => {
            GaussianFilter::new([radius; 2], sigma).map(Filter::Gaussian)
        }
    }
    .map_err(|e| parameter_error("filter", e))
}
