//! [`BsdfFlags`], the kinds of scattering a BSDF (or one sampled lobe of it)
//! performs, and [`TransportMode`], which quantity a path carries.

use std::ops::{BitOr, BitOrAssign};

/// A set of scattering properties: reflection and/or transmission, and whether
/// the lobe is diffuse, glossy or specular (a Dirac delta).
///
/// Integrators use them to skip light sampling at specular vertices (a delta
/// lobe cannot be hit by a sampled light direction), to decide whether MIS
/// applies, and (for sampled lobes) to know whether `wi` crossed the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct BsdfFlags(u8);

impl BsdfFlags {
    /// No scattering at all (a black surface).
    pub const NONE: BsdfFlags = BsdfFlags(0);
    /// Light leaves on the side it arrived from.
    pub const REFLECTION: BsdfFlags = BsdfFlags(1);
    /// Light crosses the surface.
    pub const TRANSMISSION: BsdfFlags = BsdfFlags(1 << 1);
    /// A smooth lobe over the whole hemisphere (Lambertian).
    pub const DIFFUSE: BsdfFlags = BsdfFlags(1 << 2);
    /// A peaked but non-delta lobe (rough microfacets).
    pub const GLOSSY: BsdfFlags = BsdfFlags(1 << 3);
    /// A Dirac delta: only one direction scatters; `evaluate` and `pdf` are 0.
    pub const SPECULAR: BsdfFlags = BsdfFlags(1 << 4);

    /// Whether every property in `other` is present.
    #[inline]
    pub const fn contains(self, other: BsdfFlags) -> bool {
        self.0 & other.0 == other.0
    }

    /// Whether no property is present.
    #[inline]
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Whether light can be reflected.
    #[inline]
    pub const fn is_reflective(self) -> bool {
        self.contains(Self::REFLECTION)
    }

    /// Whether light can be transmitted.
    #[inline]
    pub const fn is_transmissive(self) -> bool {
        self.contains(Self::TRANSMISSION)
    }

    /// Whether the lobe is a Dirac delta.
    #[inline]
    pub const fn is_specular(self) -> bool {
        self.contains(Self::SPECULAR)
    }

    /// Whether the lobe is diffuse.
    #[inline]
    pub const fn is_diffuse(self) -> bool {
        self.contains(Self::DIFFUSE)
    }

    /// Whether the lobe is glossy.
    #[inline]
    pub const fn is_glossy(self) -> bool {
        self.contains(Self::GLOSSY)
    }

    /// Whether some lobe is not a delta, so that `evaluate`/`pdf` can be
    /// non-zero and light sampling with MIS makes sense.
    #[inline]
    pub const fn is_non_specular(self) -> bool {
        self.0 & (Self::DIFFUSE.0 | Self::GLOSSY.0) != 0
    }
}

impl BitOr for BsdfFlags {
    type Output = BsdfFlags;
    fn bitor(self, other: BsdfFlags) -> BsdfFlags {
        BsdfFlags(self.0 | other.0)
    }
}

impl BitOrAssign for BsdfFlags {
    fn bitor_assign(&mut self, other: BsdfFlags) {
        self.0 |= other.0;
    }
}

/// Which quantity a path carries, which matters for refraction: radiance is
/// compressed by η² when it enters a denser medium (the solid angle shrinks),
/// importance is not (Veach 1997, *Robust Monte Carlo Methods for Light
/// Transport Simulation*, §5.2; pbrt-v4 §9.5.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum TransportMode {
    /// Paths traced from the camera (path tracing, BDPT camera subpaths):
    /// refraction divides the BSDF by η², the relative index along the path.
    #[default]
    Radiance,
    /// Paths traced from the lights (light tracing, BDPT light subpaths,
    /// photon mapping): no η² factor.
    Importance,
}

impl TransportMode {
    /// The mode of the subpaths of the other kind: what a bidirectional
    /// method's reverse densities are taken in.
    #[inline]
    pub fn other(self) -> Self {
        match self {
            TransportMode::Radiance => TransportMode::Importance,
            TransportMode::Importance => TransportMode::Radiance,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flag_algebra() {
        let specular_transmission = BsdfFlags::TRANSMISSION | BsdfFlags::SPECULAR;
        assert!(specular_transmission.is_transmissive());
        assert!(specular_transmission.is_specular());
        assert!(!specular_transmission.is_reflective());
        assert!(!specular_transmission.is_non_specular());
        let mut diffuse = BsdfFlags::NONE;
        assert!(diffuse.is_empty());
        diffuse |= BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE;
        assert!(diffuse.is_diffuse() && diffuse.is_non_specular() && !diffuse.is_glossy());
        assert!(diffuse.contains(BsdfFlags::NONE));
        assert_eq!(TransportMode::default(), TransportMode::Radiance);
    }
}
