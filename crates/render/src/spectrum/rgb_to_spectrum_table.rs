//! RGB → reflectance spectrum: a table of sigmoid-polynomial coefficients over
//! the linear sRGB cube, fitted by this module (Jakob and Hanika 2019, "A
//! Low-Dimensional Function Space for Efficient Spectral Upsampling", §4).
//!
//! # Table layout
//! An RGB colour in [0, 1]³ is described by the index `m` of its largest
//! component, that component z = rgb\[m\] (the brightness) and the two others
//! divided by it, x = rgb\[(m+1) mod 3\] / z and y = rgb\[(m+2) mod 3\] / z, both in
//! [0, 1]. For each m the table holds coefficients on an R × R × R grid of
//! (z, y, x): x and y uniform, z at smoothstep(smoothstep(j / (R − 1))), which
//! crowds nodes near black and near full brightness, where the coefficients
//! change fastest. Lookups interpolate the coefficients trilinearly.
//!
//! # Fitting
//! For each node the three coefficients minimise the CIE 1976 colour difference
//! between the target RGB and the RGB of the reflectance lit by D65 (the sRGB
//! white), i.e. the Lab residual is driven to zero by Gauss–Newton steps with an
//! analytic Jacobian and step halving. Coefficients are solved in a normalised
//! wavelength t = (λ − 360) / 470 for conditioning and converted to nm at the end.
//! Each column of constant (m, x, y) starts at the node j = R/5 from the grey
//! initial guess c = 0 and walks up and then down in brightness, each solve
//! starting from its neighbour's solution, as the paper does.
//!
//! Colours outside the reflectance gamut (only the sRGB primaries' extreme
//! corners come close) cannot be matched; their coefficients are kept bounded by
//! [`MAX_NORMALISED_COEFFICIENT`] so that interpolation stays well behaved.
//!
//! # The stored sRGB table
//! Fitting the table at [`DEFAULT_RGB_TABLE_RESOLUTION`] = 64 (Mitsuba 3's
//! and pbrt-v4's resolution) costs about 2.6·10¹⁰ instructions (9 s of CPU
//! time with optimised code), which every process and test binary would pay
//! at start-up. So the fitter's output is stored in
//! `crates/render/data/spectra/srgb_to_spectrum_table_64.bin`
//! ([`STORED_SRGB_TABLE_BYTES`] = 9 437 204 bytes, the format of
//! [`RgbToSpectrumTable::to_bytes`]) and [`RgbToSpectrumTable::srgb`] reads
//! it in place, from the bytes embedded in the binary: only the nodes a
//! lookup interpolates are decoded (decoding all 2.4 million values up front
//! cost every process 15 M instructions). It is exactly what [`RgbToSpectrumTable::generate`]
//! produces (a test refits a sample of columns, and the round-trip test the
//! whole table, and compares bit for bit). After changing the fitter,
//! regenerate it with
//!
//! ```text
//! cargo run --release -p render --example rgb_to_spectrum_table
//! ```
//!
//! The round trip RGB → spectrum → RGB is within 3.3·10⁻³ (mean 8.7·10⁻⁴)
//! over [0, 1]³ at resolution 32, which the renderer used until issue 15:
//! its trilinear interpolation of the coefficients darkens colours
//! systematically (the luminance of `museum.exr`'s texels upsampled as
//! illuminants −0.13 to −0.16 % in X, Y, Z; Mitsuba 3's table −0.03 %), which
//! made directly seen environment maps 0.1–0.3 % dark against Mitsuba's
//! references. Resolution 64 halves the largest error, divides the mean by
//! five and brings that bias to −0.03 to −0.05 %.

use std::borrow::Cow;
use std::sync::OnceLock;

use super::cie::{CIE_LAMBDA_MAX, CIE_LAMBDA_MIN, cie_x, cie_y, cie_z, d65_illuminant};
use super::colour::XYZ_TO_LINEAR_SRGB;
use super::error::SpectrumError;
use super::sigmoid::RgbSigmoidPolynomial;

/// Grid resolution R of the sRGB table built by [`RgbToSpectrumTable::srgb`]
/// (pbrt-v4 uses 64; see the crate tests for the round-trip error at this one).
pub const DEFAULT_RGB_TABLE_RESOLUTION: usize = 64;

/// Bound on the absolute value of each coefficient in the normalised wavelength
/// t ∈ [0, 1]. Reached only by colours the sigmoid model cannot match (at the
/// edge of the reflectance gamut), where Gauss–Newton would otherwise let the
/// coefficients grow without limit.
pub const MAX_NORMALISED_COEFFICIENT: f64 = 200.0;

/// Wavelength spacing (nm) of the quadrature used while fitting.
const FIT_WAVELENGTH_STEP: i32 = 5;

/// Gauss–Newton stops when the CIE 1976 ΔE residual falls below this.
const FIT_TOLERANCE_DELTA_E: f64 = 1e-3;

/// Gauss–Newton gives up when an iteration lowers the ΔE residual by less than
/// this fraction (the colour is out of the model's reach).
const FIT_MIN_RELATIVE_IMPROVEMENT: f64 = 1e-3;

/// Gauss–Newton iteration budget per node.
const FIT_MAX_ITERATIONS: usize = 40;

/// Lower end of the normalised wavelength t = (λ − 360) / 470.
const NORMALISED_LAMBDA_OFFSET: f64 = CIE_LAMBDA_MIN as f64;

/// Width of the wavelength range mapped to t ∈ [0, 1].
const NORMALISED_LAMBDA_WIDTH: f64 = (CIE_LAMBDA_MAX - CIE_LAMBDA_MIN) as f64;

/// Coefficients of the sigmoid model for every RGB colour in [0, 1]³ of one RGB
/// colour space (here linear sRGB under D65).
#[derive(Debug, Clone)]
pub struct RgbToSpectrumTable {
    resolution: usize,
    brightness_nodes: Vec<f32>,
    /// The nodes' coefficients c₀, c₁, c₂ in nm as little-endian `f32`s (12
    /// bytes a node, the body of [`Self::to_bytes`]), node index `((m · R +
    /// zi) · R + yi) · R + xi`: borrowed from the binary for the stored sRGB
    /// table, owned otherwise.
    coefficient_bytes: Cow<'static, [u8]>,
}

/// Bytes of one node's three coefficients.
const NODE_BYTES: usize = 12;

/// Tables are equal when their resolutions and every coefficient are
/// (compared as `f32`s, as the stored table is checked against the fitter).
impl PartialEq for RgbToSpectrumTable {
    fn eq(&self, other: &Self) -> bool {
        self.resolution == other.resolution
            && self.brightness_nodes == other.brightness_nodes
            && (0..self.node_count())
                .all(|index| self.node_coefficients(index) == other.node_coefficients(index))
    }
}

/// The brightness grid: smoothstep(smoothstep(j / (R − 1))), j = 0 … R − 1.
fn brightness_nodes(resolution: usize) -> Vec<f64> {
    let smoothstep = |x: f64| x * x * (3.0 - 2.0 * x);
    (0..resolution)
        .map(|j| smoothstep(smoothstep(j as f64 / (resolution - 1) as f64)))
        .collect()
}

impl RgbToSpectrumTable {
    /// The linear sRGB table at [`DEFAULT_RGB_TABLE_RESOLUTION`]: the stored
    /// output of the fitter (see the module docs), read in place and shared.
    /// Its coefficients are not checked for finiteness here, as
    /// [`Self::from_bytes`] does, but by a unit test.
    pub fn srgb() -> &'static RgbToSpectrumTable {
        static TABLE: OnceLock<RgbToSpectrumTable> = OnceLock::new();
        TABLE.get_or_init(|| {
            let resolution = Self::stored_resolution(STORED_SRGB_TABLE)
                .expect("the stored sRGB table is well formed (a unit test checks it)");
            debug_assert_eq!(resolution, DEFAULT_RGB_TABLE_RESOLUTION);
            Self::with_coefficient_bytes(
                resolution,
                Cow::Borrowed(&STORED_SRGB_TABLE[TABLE_HEADER_BYTES..]),
            )
        })
    }

    /// The table of `resolution` with the coefficients `coefficient_bytes`
    /// (of the right length).
    fn with_coefficient_bytes(resolution: usize, coefficient_bytes: Cow<'static, [u8]>) -> Self {
        debug_assert_eq!(
            coefficient_bytes.len(),
            stored_table_size(resolution) - TABLE_HEADER_BYTES
        );
        Self {
            resolution,
            brightness_nodes: brightness_nodes(resolution)
                .iter()
                .map(|&z| z as f32)
                .collect(),
            coefficient_bytes,
        }
    }

    /// The number of nodes, 3 R³.
    fn node_count(&self) -> usize {
        self.coefficient_bytes.len() / NODE_BYTES
    }

    /// The coefficients of the node of index `index` (see [`Self::node`]).
    #[inline]
    fn node_coefficients(&self, index: usize) -> [f32; 3] {
        let node = &self.coefficient_bytes[NODE_BYTES * index..NODE_BYTES * (index + 1)];
        std::array::from_fn(|i| {
            f32::from_le_bytes(node[4 * i..4 * i + 4].try_into().expect("four bytes"))
        })
    }

    /// The table as bytes: [`TABLE_MAGIC`], the resolution R as a
    /// little-endian `u32`, then the 3 R³ nodes' coefficients (c₀, c₁, c₂ in
    /// nm, little-endian `f32`) in the order of [`Self::node`]'s index
    /// `((m · R + zi) · R + yi) · R + xi`. The brightness nodes are not stored
    /// (they follow from R).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut bytes = Vec::with_capacity(stored_table_size(self.resolution));
        bytes.extend_from_slice(TABLE_MAGIC);
        bytes.extend_from_slice(&(self.resolution as u32).to_le_bytes());
        bytes.extend_from_slice(&self.coefficient_bytes);
        bytes
    }

    /// The resolution in the header of `bytes` (a table as written by
    /// [`Self::to_bytes`]), after checking the magic, the resolution's range
    /// and the length.
    fn stored_resolution(bytes: &[u8]) -> Result<usize, SpectrumError> {
        let malformed = |reason: String| SpectrumError::MalformedTableData { reason };
        if bytes.len() < TABLE_HEADER_BYTES || &bytes[..TABLE_MAGIC.len()] != TABLE_MAGIC {
            return Err(malformed("it does not start with the table magic".into()));
        }
        let resolution_bytes: [u8; 4] = bytes[TABLE_MAGIC.len()..TABLE_HEADER_BYTES]
            .try_into()
            .expect("four bytes");
        let resolution = u32::from_le_bytes(resolution_bytes) as usize;
        if !(2..=1024).contains(&resolution) {
            return Err(malformed(format!(
                "resolution {resolution} is not in 2..=1024"
            )));
        }
        let expected = stored_table_size(resolution);
        if bytes.len() != expected {
            return Err(malformed(format!(
                "{} bytes where resolution {resolution} needs {expected}",
                bytes.len()
            )));
        }
        Ok(resolution)
    }

    /// Reads a table written by [`Self::to_bytes`]; fails with what is wrong
    /// (magic, resolution, length, non-finite coefficients).
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, SpectrumError> {
        let resolution = Self::stored_resolution(bytes)?;
        let table = Self::with_coefficient_bytes(
            resolution,
            Cow::Owned(bytes[TABLE_HEADER_BYTES..].to_vec()),
        );
        if let Some(index) = (0..table.node_count()).position(|index| {
            table
                .node_coefficients(index)
                .iter()
                .any(|value| !value.is_finite())
        }) {
            return Err(SpectrumError::MalformedTableData {
                reason: format!("node {index} has a non-finite coefficient"),
            });
        }
        Ok(table)
    }

    /// Fits the linear sRGB table at resolution `resolution` (≥ 2), using the
    /// machine's cores (plain threads, so this is safe to call from inside a
    /// rayon task).
    pub fn generate(resolution: usize) -> Result<Self, SpectrumError> {
        if resolution < 2 {
            return Err(SpectrumError::TableResolutionTooSmall { resolution });
        }
        let fitter = SigmoidFitter::srgb();
        let nodes = brightness_nodes(resolution);
        let column_count = 3 * resolution * resolution;
        let threads = std::thread::available_parallelism()
            .map_or(1, usize::from)
            .clamp(1, 8);
        let columns_per_thread = column_count.div_ceil(threads);
        // Each column (m, yi, xi) is fitted independently along z.
        let columns: Vec<Vec<[f64; 3]>> = std::thread::scope(|scope| {
            let handles: Vec<_> = (0..threads)
                .map(|thread| {
                    let fitter = &fitter;
                    let nodes = &nodes;
                    scope.spawn(move || {
                        let start = (thread * columns_per_thread).min(column_count);
                        let end = ((thread + 1) * columns_per_thread).min(column_count);
                        (start..end)
                            .map(|column| fitter.fit_column(column, resolution, nodes))
                            .collect::<Vec<_>>()
                    })
                })
                .collect();
            handles
                .into_iter()
                .flat_map(|handle| handle.join().expect("fitting thread panicked"))
                .collect()
        });
        let mut coefficient_bytes =
            vec![0_u8; 3 * resolution * resolution * resolution * NODE_BYTES];
        for (column, solutions) in columns.iter().enumerate() {
            for (zi, solution) in solutions.iter().enumerate() {
                let start = NODE_BYTES * column_node_index(column, zi, resolution);
                for (i, value) in normalised_to_nm(*solution).into_iter().enumerate() {
                    coefficient_bytes[start + 4 * i..start + 4 * i + 4]
                        .copy_from_slice(&value.to_le_bytes());
                }
            }
        }
        Ok(Self::with_coefficient_bytes(
            resolution,
            Cow::Owned(coefficient_bytes),
        ))
    }

    /// The grid resolution R.
    pub fn resolution(&self) -> usize {
        self.resolution
    }

    /// The brightness values z of the grid nodes, increasing from 0 to 1.
    pub fn brightness_nodes(&self) -> &[f32] {
        &self.brightness_nodes
    }

    /// The stored coefficients of node (`max_index`, `zi`, `yi`, `xi`).
    pub fn node(&self, max_index: usize, zi: usize, yi: usize, xi: usize) -> RgbSigmoidPolynomial {
        let r = self.resolution;
        let [c0, c1, c2] = self.node_coefficients(((max_index * r + zi) * r + yi) * r + xi);
        RgbSigmoidPolynomial::new(c0, c1, c2)
    }

    /// The sigmoid-polynomial reflectance whose colour under D65 is the linear
    /// sRGB `rgb`. Components are clamped to [0, 1] (NaN counts as 0); greys
    /// (equal components) get the exact constant spectrum.
    pub fn lookup(&self, rgb: [f32; 3]) -> RgbSigmoidPolynomial {
        let rgb = rgb.map(|value| {
            if value.is_nan() {
                0.0
            } else {
                value.clamp(0.0, 1.0)
            }
        });
        if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
            return RgbSigmoidPolynomial::constant(rgb[0]);
        }
        let max_index = if rgb[0] >= rgb[1] && rgb[0] >= rgb[2] {
            0
        } else if rgb[1] >= rgb[2] {
            1
        } else {
            2
        };
        let z = rgb[max_index];
        let last = (self.resolution - 1) as f32;
        let x = rgb[(max_index + 1) % 3] / z * last;
        let y = rgb[(max_index + 2) % 3] / z * last;
        let xi = (x as usize).min(self.resolution - 2);
        let yi = (y as usize).min(self.resolution - 2);
        let zi = self
            .brightness_nodes
            .partition_point(|&node| node <= z)
            .saturating_sub(1)
            .min(self.resolution - 2);
        let dx = x - xi as f32;
        let dy = y - yi as f32;
        let dz = (z - self.brightness_nodes[zi])
            / (self.brightness_nodes[zi + 1] - self.brightness_nodes[zi]);
        let r = self.resolution;
        let mut result = [0.0_f32; 3];
        for corner in 0..8 {
            let (ox, oy, oz) = (corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
            let weight = (if ox == 1 { dx } else { 1.0 - dx })
                * (if oy == 1 { dy } else { 1.0 - dy })
                * (if oz == 1 { dz } else { 1.0 - dz });
            let index = ((max_index * r + zi + oz) * r + yi + oy) * r + xi + ox;
            for (sum, value) in result.iter_mut().zip(self.node_coefficients(index)) {
                *sum += weight * value;
            }
        }
        RgbSigmoidPolynomial::new(result[0], result[1], result[2])
    }
}

/// The bytes [`RgbToSpectrumTable::to_bytes`] starts with.
pub const TABLE_MAGIC: &[u8; 16] = b"lqmc rgb2spec v1";

/// The stored output of the fitter for linear sRGB at
/// [`DEFAULT_RGB_TABLE_RESOLUTION`] (see the module docs).
const STORED_SRGB_TABLE: &[u8] = include_bytes!("../../data/spectra/srgb_to_spectrum_table_64.bin");

/// Size in bytes of the stored sRGB table.
pub const STORED_SRGB_TABLE_BYTES: usize = stored_table_size(DEFAULT_RGB_TABLE_RESOLUTION);

/// Bytes before the coefficients in [`RgbToSpectrumTable::to_bytes`]: the
/// magic and the resolution.
const TABLE_HEADER_BYTES: usize = TABLE_MAGIC.len() + 4;

/// Size in bytes of [`RgbToSpectrumTable::to_bytes`] at `resolution`.
const fn stored_table_size(resolution: usize) -> usize {
    TABLE_HEADER_BYTES + 3 * resolution * resolution * resolution * NODE_BYTES
}

/// Index in the coefficient array of node `zi` of fitting column `column`
/// = (m · R + yi) · R + xi.
fn column_node_index(column: usize, zi: usize, resolution: usize) -> usize {
    let max_index = column / (resolution * resolution);
    let yi = (column / resolution) % resolution;
    let xi = column % resolution;
    ((max_index * resolution + zi) * resolution + yi) * resolution + xi
}

/// Converts coefficients of x(t), t = (λ − a) / w, to coefficients of x(λ):
/// c₀ t² + c₁ t + c₂ = (c₀/w²) λ² + (c₁/w − 2 a c₀/w²) λ + (c₀ a²/w² − c₁ a/w + c₂).
fn normalised_to_nm(c: [f64; 3]) -> [f32; 3] {
    let a = NORMALISED_LAMBDA_OFFSET;
    let w = NORMALISED_LAMBDA_WIDTH;
    [
        (c[0] / (w * w)) as f32,
        (c[1] / w - 2.0 * a * c[0] / (w * w)) as f32,
        (c[0] * a * a / (w * w) - c[1] * a / w + c[2]) as f32,
    ]
}

/// CIE 1976 L*a*b* of `xyz` relative to the white `white`.
fn xyz_to_lab(xyz: [f64; 3], white: [f64; 3]) -> [f64; 3] {
    let f = |t: f64| lab_f(t).0;
    let (fx, fy, fz) = (
        f(xyz[0] / white[0]),
        f(xyz[1] / white[1]),
        f(xyz[2] / white[2]),
    );
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// The CIELAB companding function f(t) and its derivative f′(t)
/// (CIE 15:2004 §8.2.1: cube root above (6/29)³, linear below).
fn lab_f(t: f64) -> (f64, f64) {
    const DELTA: f64 = 6.0 / 29.0;
    if t > DELTA * DELTA * DELTA {
        let cube_root = t.cbrt();
        (cube_root, 1.0 / (3.0 * cube_root * cube_root))
    } else {
        let slope = 1.0 / (3.0 * DELTA * DELTA);
        (t * slope + 4.0 / 29.0, slope)
    }
}

/// Inverse of a 3×3 matrix (None if singular).
fn invert_3x3(m: [[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let cofactor =
        |r0: usize, r1: usize, c0: usize, c1: usize| m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0];
    let adjugate = [
        [
            cofactor(1, 2, 1, 2),
            -cofactor(0, 2, 1, 2),
            cofactor(0, 1, 1, 2),
        ],
        [
            -cofactor(1, 2, 0, 2),
            cofactor(0, 2, 0, 2),
            -cofactor(0, 1, 0, 2),
        ],
        [
            cofactor(1, 2, 0, 1),
            -cofactor(0, 2, 0, 1),
            cofactor(0, 1, 0, 1),
        ],
    ];
    let determinant =
        m[0][0] * adjugate[0][0] + m[0][1] * adjugate[1][0] + m[0][2] * adjugate[2][0];
    if determinant.abs() < 1e-300 {
        return None;
    }
    Some(adjugate.map(|row| row.map(|value| value / determinant)))
}

/// Solves `matrix · x = rhs` (None if singular).
fn solve_3x3(matrix: [[f64; 3]; 3], rhs: [f64; 3]) -> Option<[f64; 3]> {
    let inverse = invert_3x3(matrix)?;
    Some(inverse.map(|row| row[0] * rhs[0] + row[1] * rhs[1] + row[2] * rhs[2]))
}

/// The quadrature and colour-space data the fit needs, all in f64.
struct SigmoidFitter {
    /// Normalised wavelength t of each quadrature node.
    normalised_lambdas: Vec<f64>,
    /// Weight of each node for X, Y, Z: step · D65(λ) · (x̄, ȳ, z̄)(λ) / Σ step · D65 ȳ,
    /// so a reflectance of 1 has Y = 1.
    xyz_weights: Vec<[f64; 3]>,
    /// XYZ of the white reflectance 1 under D65 with this quadrature.
    white: [f64; 3],
    /// Linear sRGB → XYZ: the exact inverse of [`XYZ_TO_LINEAR_SRGB`], so that
    /// spectrum → XYZ → sRGB with that matrix reproduces the fitted RGB.
    rgb_to_xyz: [[f64; 3]; 3],
}

impl SigmoidFitter {
    /// Fitting data for linear sRGB lit by D65.
    fn srgb() -> Self {
        let lambdas: Vec<i32> = (CIE_LAMBDA_MIN..=CIE_LAMBDA_MAX)
            .step_by(FIT_WAVELENGTH_STEP as usize)
            .collect();
        let illuminant = d65_illuminant();
        let raw: Vec<[f64; 3]> = lambdas
            .iter()
            .map(|&lambda| {
                let lambda = lambda as f32;
                let power = f64::from(illuminant.evaluate(lambda));
                [
                    power * f64::from(cie_x().evaluate(lambda)),
                    power * f64::from(cie_y().evaluate(lambda)),
                    power * f64::from(cie_z().evaluate(lambda)),
                ]
            })
            .collect();
        let luminance: f64 = raw.iter().map(|weight| weight[1]).sum();
        let xyz_weights: Vec<[f64; 3]> = raw
            .iter()
            .map(|weight| weight.map(|value| value / luminance))
            .collect();
        let mut white = [0.0; 3];
        for weight in &xyz_weights {
            for (sum, value) in white.iter_mut().zip(weight) {
                *sum += value;
            }
        }
        let xyz_to_rgb = XYZ_TO_LINEAR_SRGB.map(|row| row.map(f64::from));
        Self {
            normalised_lambdas: lambdas
                .iter()
                .map(|&lambda| {
                    (f64::from(lambda) - NORMALISED_LAMBDA_OFFSET) / NORMALISED_LAMBDA_WIDTH
                })
                .collect(),
            xyz_weights,
            white,
            rgb_to_xyz: invert_3x3(xyz_to_rgb).expect("the sRGB matrix is invertible"),
        }
    }

    /// XYZ of the reflectance with normalised coefficients `c`, and its
    /// derivatives: `jacobian[i][j]` = ∂XYZᵢ / ∂cⱼ.
    fn xyz_and_jacobian(&self, c: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
        let mut xyz = [0.0; 3];
        let mut jacobian = [[0.0; 3]; 3];
        for (&t, weight) in self.normalised_lambdas.iter().zip(&self.xyz_weights) {
            let x = (c[0] * t + c[1]) * t + c[2];
            let root = (1.0 + x * x).sqrt();
            let sigmoid = 0.5 + x / (2.0 * root);
            let slope = 1.0 / (2.0 * root * root * root);
            let powers = [t * t, t, 1.0];
            for i in 0..3 {
                xyz[i] += weight[i] * sigmoid;
                for j in 0..3 {
                    jacobian[i][j] += weight[i] * slope * powers[j];
                }
            }
        }
        (xyz, jacobian)
    }

    /// Lab of the reflectance with coefficients `c`, and ∂Lab/∂c.
    fn lab_and_jacobian(&self, c: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
        let (xyz, xyz_jacobian) = self.xyz_and_jacobian(c);
        let lab = xyz_to_lab(xyz, self.white);
        let derivative: [f64; 3] =
            std::array::from_fn(|i| lab_f(xyz[i] / self.white[i]).1 / self.white[i]);
        let mut jacobian = [[0.0; 3]; 3];
        for j in 0..3 {
            let (dx, dy, dz) = (
                derivative[0] * xyz_jacobian[0][j],
                derivative[1] * xyz_jacobian[1][j],
                derivative[2] * xyz_jacobian[2][j],
            );
            jacobian[0][j] = 116.0 * dy;
            jacobian[1][j] = 500.0 * (dx - dy);
            jacobian[2][j] = 200.0 * (dy - dz);
        }
        (lab, jacobian)
    }

    /// Gauss–Newton from `start` towards the coefficients whose reflectance has
    /// the linear sRGB `rgb`. Returns the best coefficients found.
    fn fit(&self, rgb: [f64; 3], start: [f64; 3]) -> [f64; 3] {
        let xyz = self
            .rgb_to_xyz
            .map(|row| row[0] * rgb[0] + row[1] * rgb[1] + row[2] * rgb[2]);
        let target = xyz_to_lab(xyz, self.white);
        let residual_of =
            |lab: [f64; 3]| [lab[0] - target[0], lab[1] - target[1], lab[2] - target[2]];
        let norm = |r: [f64; 3]| (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        let mut c = start;
        let (mut lab, mut jacobian) = self.lab_and_jacobian(c);
        let mut error = norm(residual_of(lab));
        for _ in 0..FIT_MAX_ITERATIONS {
            if error < FIT_TOLERANCE_DELTA_E {
                break;
            }
            let residual = residual_of(lab);
            let Some(step) = solve_3x3(jacobian, residual.map(|value| -value)) else {
                break;
            };
            // Step halving: accept the first step length that lowers the error.
            let mut length = 1.0;
            let mut improved = false;
            for _ in 0..12 {
                let mut candidate: [f64; 3] = std::array::from_fn(|i| c[i] + length * step[i]);
                let largest = candidate.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                if largest > MAX_NORMALISED_COEFFICIENT {
                    candidate = candidate.map(|value| value * MAX_NORMALISED_COEFFICIENT / largest);
                }
                let (candidate_lab, candidate_jacobian) = self.lab_and_jacobian(candidate);
                let candidate_error = norm(residual_of(candidate_lab));
                if candidate_error < error {
                    // Stagnation (a colour the model cannot reach): stop.
                    if candidate_error > (1.0 - FIT_MIN_RELATIVE_IMPROVEMENT) * error {
                        return candidate;
                    }
                    c = candidate;
                    lab = candidate_lab;
                    jacobian = candidate_jacobian;
                    error = candidate_error;
                    improved = true;
                    break;
                }
                length *= 0.5;
            }
            if !improved {
                break;
            }
        }
        c
    }

    /// Fits every brightness node of column `column` = (m · R + yi) · R + xi,
    /// walking up and down in brightness from node R/5 (warm starts).
    fn fit_column(&self, column: usize, resolution: usize, nodes: &[f64]) -> Vec<[f64; 3]> {
        let max_index = column / (resolution * resolution);
        let x = (column % resolution) as f64 / (resolution - 1) as f64;
        let y = ((column / resolution) % resolution) as f64 / (resolution - 1) as f64;
        let rgb_at = |z: f64| {
            let mut rgb = [0.0; 3];
            rgb[max_index] = z;
            rgb[(max_index + 1) % 3] = x * z;
            rgb[(max_index + 2) % 3] = y * z;
            rgb
        };
        let start_node = resolution / 5;
        let mut solutions = vec![[0.0; 3]; resolution];
        let mut c = [0.0; 3];
        for zi in start_node..resolution {
            c = self.fit(rgb_at(nodes[zi]), c);
            solutions[zi] = c;
        }
        c = solutions[start_node];
        for zi in (0..start_node).rev() {
            c = self.fit(rgb_at(nodes[zi]), c);
            solutions[zi] = c;
        }
        solutions
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coefficient_conversion_preserves_the_polynomial() {
        let normalised = [3.0, -2.0, 0.5];
        let [c0, c1, c2] = normalised_to_nm(normalised);
        for lambda in [360.0_f64, 500.0, 830.0] {
            let t = (lambda - 360.0) / 470.0;
            let expected = (normalised[0] * t + normalised[1]) * t + normalised[2];
            let actual = (f64::from(c0) * lambda + f64::from(c1)) * lambda + f64::from(c2);
            assert!((expected - actual).abs() < 1e-4, "{expected} vs {actual}");
        }
    }

    #[test]
    fn lab_jacobian_matches_finite_differences() {
        let fitter = SigmoidFitter::srgb();
        let c = [1.5, -2.0, 0.3];
        let (_, jacobian) = fitter.lab_and_jacobian(c);
        let h = 1e-6;
        for j in 0..3 {
            let mut plus = c;
            let mut minus = c;
            plus[j] += h;
            minus[j] -= h;
            let (lab_plus, _) = fitter.lab_and_jacobian(plus);
            let (lab_minus, _) = fitter.lab_and_jacobian(minus);
            for i in 0..3 {
                let numeric = (lab_plus[i] - lab_minus[i]) / (2.0 * h);
                assert!(
                    (numeric - jacobian[i][j]).abs() < 1e-5 * (1.0 + numeric.abs()),
                    "{i},{j}"
                );
            }
        }
    }

    #[test]
    fn fits_a_single_colour() {
        let fitter = SigmoidFitter::srgb();
        let rgb = [0.6, 0.3, 0.1];
        let c = fitter.fit(rgb, [0.0; 3]);
        let (xyz, _) = fitter.xyz_and_jacobian(c);
        let back = XYZ_TO_LINEAR_SRGB.map(|row| {
            f64::from(row[0]) * xyz[0] + f64::from(row[1]) * xyz[1] + f64::from(row[2]) * xyz[2]
        });
        for (value, expected) in back.iter().zip(rgb) {
            assert!((value - expected).abs() < 1e-5, "{back:?}");
        }
    }

    #[test]
    fn stored_table_is_what_the_fitter_produces() {
        let table = RgbToSpectrumTable::srgb();
        let resolution = table.resolution();
        assert_eq!(resolution, DEFAULT_RGB_TABLE_RESOLUTION);
        assert_eq!(STORED_SRGB_TABLE.len(), STORED_SRGB_TABLE_BYTES);
        let fitter = SigmoidFitter::srgb();
        let nodes = brightness_nodes(resolution);
        let column_count = 3 * resolution * resolution;
        // 13 columns spread over the three maximum channels and all (x, y),
        // among them the corners x = y = 0 (saturated primaries) and x = y = 1.
        let mut columns: Vec<usize> = (0..11).map(|i| i * 283 % column_count).collect();
        columns.extend([resolution * resolution - 1, column_count - 1]);
        for column in columns {
            for (zi, solution) in fitter
                .fit_column(column, resolution, &nodes)
                .into_iter()
                .enumerate()
            {
                let stored = table.node_coefficients(column_node_index(column, zi, resolution));
                assert_eq!(
                    stored,
                    normalised_to_nm(solution),
                    "column {column}, node {zi}: regenerate the table (see the module docs)"
                );
            }
        }
        let expected_nodes: Vec<f32> = nodes.iter().map(|&z| z as f32).collect();
        assert_eq!(table.brightness_nodes(), expected_nodes.as_slice());
    }

    /// [`RgbToSpectrumTable::srgb`] reads the stored table without the
    /// checks of [`RgbToSpectrumTable::from_bytes`]: they pass, and give the
    /// same table.
    #[test]
    fn stored_table_is_well_formed() {
        let checked = RgbToSpectrumTable::from_bytes(STORED_SRGB_TABLE).unwrap();
        assert_eq!(&checked, RgbToSpectrumTable::srgb());
        assert_eq!(checked.to_bytes(), STORED_SRGB_TABLE);
    }

    #[test]
    fn bytes_round_trip_and_bad_data_is_rejected() {
        let table = RgbToSpectrumTable::generate(3).unwrap();
        let bytes = table.to_bytes();
        assert_eq!(bytes.len(), stored_table_size(3));
        assert_eq!(RgbToSpectrumTable::from_bytes(&bytes).unwrap(), table);
        let truncated = RgbToSpectrumTable::from_bytes(&bytes[..bytes.len() - 1]);
        assert!(matches!(
            truncated,
            Err(SpectrumError::MalformedTableData { .. })
        ));
        let mut wrong_magic = bytes.clone();
        wrong_magic[0] ^= 1;
        assert!(RgbToSpectrumTable::from_bytes(&wrong_magic).is_err());
        let mut not_finite = bytes.clone();
        let last = not_finite.len() - 4;
        not_finite[last..].copy_from_slice(&f32::NAN.to_le_bytes());
        let message = RgbToSpectrumTable::from_bytes(&not_finite)
            .unwrap_err()
            .to_string();
        assert!(message.contains("non-finite"), "{message}");
        assert!(RgbToSpectrumTable::from_bytes(b"short").is_err());
    }

    #[test]
    fn rejects_tiny_resolutions() {
        assert!(RgbToSpectrumTable::generate(1).is_err());
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn matrix_inverse() {
        let m = [[2.0, 1.0, 0.0], [0.0, 3.0, 1.0], [1.0, 0.0, 4.0]];
        let inverse = invert_3x3(m).unwrap();
        for i in 0..3 {
            for j in 0..3 {
                let product: f64 = (0..3).map(|k| m[i][k] * inverse[k][j]).sum();
                assert!((product - if i == j { 1.0 } else { 0.0 }).abs() < 1e-12);
            }
        }
        assert!(invert_3x3([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]]).is_none());
    }
}
