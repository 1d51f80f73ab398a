//! [`Imported`]: coefficients read back from an engine format, what each
//! format's reader (under `export/`) gives [`crate::read_coefficients`].

use glam::DVec3;
use shlight_core::sh::{Frame, ShCoeffs};

use crate::CoeffFile;
use crate::quantity::Quantity;

/// Coefficients read back from an engine format.
#[derive(Clone, Debug)]
pub struct Imported {
    /// shlight basis (CS phase), linear RGB.
    pub coeffs: ShCoeffs<DVec3>,
    /// What they hold.
    pub quantity: Quantity,
    /// The frame they are in (engines are y-up).
    pub frame: Frame,
    /// What was read, for the provenance (`layout`) of the coefficient file.
    pub source: &'static str,
}

impl Imported {
    /// A coefficient file holding these coefficients, its provenance naming
    /// `name` as the input, what was read as the layout, and `convert` as
    /// the method.
    #[must_use]
    pub fn into_coeff_file(self, name: &str) -> CoeffFile {
        let mut file = CoeffFile::new(self.coeffs, self.frame, self.quantity);
        file.provenance.input = name.to_string();
        file.provenance.layout = self.source.to_string();
        file.provenance.method = "convert".to_string();
        file.provenance.window = "unknown".to_string();
        file
    }
}
