//! Maya ASCII (`.ma`) import: a reader for the MEL subset Maya writes and the mapping of
//! Maya's nodes onto sinew's plugins, with Maya's conventions kept (units, short attribute
//! names, the deformer plumbing collapsed into a chain). See `docs/maya-import.md`.
//!
//! Layers, each its own module: [`lex`] (tokens with byte spans), [`parse`] (statements
//! into the [`scene`] model), [`values`] (typed `setAttr` values), [`plug`] and [`names`]
//! (plug paths, DAG paths), [`units`] (the unit rules).

pub mod lex;
pub mod names;
pub mod parse;
pub mod plug;
pub mod scene;
pub mod units;
pub mod values;
