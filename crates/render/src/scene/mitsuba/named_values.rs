//! Values Mitsuba 3 knows by name: the indices of refraction of its
//! `dielectric` family (`int_ior="bk7"`) and the conductor `material`
//! names of its `conductor` family.
//!
//! The index table is `render::scene::spectra::named_ior` (Mitsuba 3's
//! `dielectric` documentation, values at 589 nm).

use super::super::description::SpectrumDescription;

/// The index of refraction Mitsuba 3 gives `name`, if it knows it (the
/// shared table of `render::scene::spectra::named_ior`), ignoring case and
/// surrounding space.
pub fn named_ior(name: &str) -> Option<f32> {
    super::super::spectra::named_ior(&name.trim().to_ascii_lowercase())
}

/// The conductor names of Mitsuba 3's `conductor` documentation (measured
/// data of its `data/ior` directory); `none` is a perfect mirror.
const CONDUCTORS: &[&str] = &[
    "a-C", "Ag", "Al", "AlAs", "AlSb", "Au", "Be", "Cr", "CsI", "Cu", "Cu2O", "CuO", "d-C", "Hg",
    "HgTe", "Ir", "K", "Li", "MgO", "Mo", "Na_palik", "Nb", "Ni_palik", "Rh", "Se", "SiC", "SnTe",
    "Ta", "Te", "ThF4", "TiC", "TiN", "TiO2", "VC", "V_palik", "VN", "W",
];

/// The spectra of a Mitsuba conductor name: `metal-NAME-eta` and
/// `metal-NAME-k` (pbrt-v4's naming of measured metals, e.g. `metal-Au-eta`;
/// the materials code resolves them, including names pbrt-v4 lacks).
/// `None` for an unknown name.
pub fn conductor_spectra(name: &str) -> Option<(SpectrumDescription, SpectrumDescription)> {
    let known = CONDUCTORS.iter().find(|known| **known == name.trim())?;
    Some((
        SpectrumDescription::Named(format!("metal-{known}-eta")),
        SpectrumDescription::Named(format!("metal-{known}-k")),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn named_iors() {
        assert_eq!(named_ior("bk7"), Some(1.5046));
        assert_eq!(named_ior("Water"), Some(1.3330));
        assert_eq!(named_ior("air"), Some(1.000277));
        assert_eq!(named_ior("unobtainium"), None);
    }

    #[test]
    fn conductor_names_map_to_metal_spectra() {
        assert_eq!(
            conductor_spectra("Au"),
            Some((
                SpectrumDescription::Named("metal-Au-eta".into()),
                SpectrumDescription::Named("metal-Au-k".into())
            ))
        );
        assert!(conductor_spectra("gold").is_none());
    }
}
