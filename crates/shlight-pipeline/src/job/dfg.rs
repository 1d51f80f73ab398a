//! `dfg`: the DFG (split-sum BRDF) table an engine reads beside its
//! prefiltered environment ([`DfgRequest`] → [`DfgPlan`] → [`dfg`]).

use std::path::Path;

use shlight_specular::{DfgForm, DfgTable, TargetEngine};

use crate::hooks::{Hooks, Progress};
use crate::specular::write_dfg;
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// A DFG table as a front end asks for it, before [`DfgRequest::check`].
#[derive(Clone, Copy, Debug)]
pub struct DfgRequest {
    /// The engine whose form (and masking term) to write.
    pub engine: TargetEngine,
    /// Texels per side.
    pub size: usize,
    /// Samples per texel.
    pub samples: u32,
}

/// A checked [`DfgRequest`].
#[derive(Clone, Copy, Debug)]
pub struct DfgPlan(DfgRequest);

impl DfgRequest {
    /// The plan, after shlight-specular's limits ([`DfgTable::check`]).
    ///
    /// # Errors
    /// A refused size or sample count, naming the setting as `spelling`
    /// does.
    pub fn check(&self, spelling: Spelling) -> Result<DfgPlan> {
        DfgTable::check(self.size, self.samples)
            .map_err(|e| PipelineError::new(format!("{}: {e}", spelling.option(e.setting()))))?;
        Ok(DfgPlan(*self))
    }
}

/// What each channel of a written table holds, and its axes.
#[must_use]
pub fn dfg_channels(form: DfgForm) -> &'static str {
    match form {
        DfgForm::Multiscatter => {
            "red: bias of F0 (B), green: scale + bias (A + B); x = n.v, y = perceptual roughness (top row 1)"
        }
        DfgForm::ScaleBias => {
            "red: scale of F0 (A), green: bias (B); x = n.v, y = perceptual roughness (top row 1)"
        }
    }
}

/// `shlight dfg`: computes the table (rows in parallel) and writes it to
/// `output` (`.exr` floats or `.png` 8-bit values, [`write_dfg`]),
/// atomically; notes what its channels hold ([`dfg_channels`]).
///
/// # Errors
/// The output's extension is neither, or it cannot be written.
pub fn dfg(output: &Path, plan: &DfgPlan, hooks: &dyn Hooks) -> Result<DfgTable> {
    let DfgRequest {
        engine,
        size,
        samples,
    } = plan.0;
    hooks.progress(Progress::Step("DFG table"));
    let table = DfgTable::for_engine(engine, size, samples);
    write_dfg(&table, output)?;
    hooks.note(dfg_channels(table.form));
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_are_shlight_specular_s_named_per_front_end() {
        let big = DfgRequest {
            engine: TargetEngine::Filament,
            size: DfgTable::MAX_SIZE + 1,
            samples: 1,
        };
        let e = big.check(Spelling::CommandLine).unwrap_err();
        assert!(e.message().starts_with("--size: "), "{e}");
        assert!(e.message().contains("from 1 to 4096"), "{e}");
        let none = DfgRequest {
            samples: 0,
            size: 16,
            ..big
        };
        let e = none.check(Spelling::Python).unwrap_err();
        assert_eq!(e.message(), "samples: the sample count must be at least 1");
        assert!(
            DfgRequest {
                size: DfgTable::MAX_SIZE,
                ..none
            }
            .check(Spelling::Python)
            .is_err()
        );
        assert!(
            DfgRequest { samples: 1, ..none }
                .check(Spelling::Python)
                .is_ok()
        );
    }
}
