//! Values Mitsuba 3 knows by name: the indices of refraction of its
//! `dielectric` family (`int_ior="bk7"`) and the conductor `material`
//! names of its `conductor` family.
//!
//! The index table is the one Mitsuba 3's documentation lists for the
//! `dielectric` plugin (values at 589 nm). It is private to this loader for
//! now; `render::scene::spectra::named_ior` (being added by another helper)
//! should replace it when merged.

use super::super::description::SpectrumDescription;

/// Mitsuba 3's named indices of refraction (its `dielectric` documentation).
const NAMED_IORS: &[(&str, f32)] = &[
    ("vacuum", 1.0),
    ("helium", 1.00004),
    ("hydrogen", 1.00013),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// The index of refraction Mitsuba 3 gives `name`, if it knows it.
pub fn named_ior(name: &str) -> Option<f32> {
    let name = name.trim().to_ascii_lowercase();
    NAMED_IORS
        .iter()
        .find(|(known, _)| *known == name)
        .map(|(_, value)| *value)
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
