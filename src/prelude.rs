//! The types most programs need: `use sinew::prelude::*;`.

pub use crate::default_registry;
pub use sinew_core::{
    evaluate_batch, AttrType, CompileOptions, Error, Graph, Instance, NodeId, Plug, PlugHandle, Program, Registry,
    Time, Value,
};
