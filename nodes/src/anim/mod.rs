//! Animation curves: Maya-compatible key/tangent evaluation ([`curve`]) and
//! the animCurve node plugins built on it.

pub mod curve;
mod key;
mod segment;
mod tangents;
