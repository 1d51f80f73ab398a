//! The fixed-size SH types (placeholder doc).

pub(crate) mod array_eval;
pub(crate) mod impl_macros;
pub(crate) mod rotation_l2;
pub(crate) mod sh_l1;
pub(crate) mod sh_l2;
