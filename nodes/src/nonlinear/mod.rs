//! Maya's nonLinear deformers: bend, twist, squash, flare, sine and wave, each a handle shape
//! (`deformBend` ...) whose `deformerData` drives a `nonLinear` deformer.
//!
//! | module | what it is for |
//! | --- | --- |
//! | [`funcs`] | the six point functions in handle space, with their formulas and sources |
//! | [`nodes`] | `deformBend`, `deformTwist`, `deformSquash`, `deformFlare`, `deformSine`, `deformWave`, `nonLinear` |

pub mod funcs;
pub mod nodes;

#[cfg(test)]
mod tests;

pub use nodes::register;
