//! The fixed-size SH types for engines' hot path: [`ShL1`](crate::sh::ShL1),
//! [`ShL2`](crate::sh::ShL2) and their RGB forms (`sh_l1.rs`, `sh_l2.rs`),
//! their rotation ([`ShRotationL2`](crate::sh::ShRotationL2),
//! `rotation_l2.rs`), the array maths they share (`array_eval.rs`: the
//! evaluation by monomials, `A_l`, truncation) and the methods written for
//! all four by macros (`impl_macros.rs`). `impl_macros.rs` uses the rotation
//! and the array maths, and the rotation the array maths; nothing depends
//! back.

pub(crate) mod array_eval;
pub(crate) mod impl_macros;
pub(crate) mod rotation_l2;
pub(crate) mod sh_l1;
pub(crate) mod sh_l2;
