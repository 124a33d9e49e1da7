//! Interchange file formats as pure readers and writers over plain Rust structs:
//! BVH motion capture in, glTF 2.0 in and out, Wavefront OBJ in and out. Nothing here touches the graph; the
//! importer and baker map these structs to and from graph nodes.

pub mod bake;
mod bake_channels;
mod bake_geometry;
pub mod bake_morphs;
pub mod bvh;
pub mod corrective;
mod gltf_binary;
pub mod gltf_read;
pub mod gltf_write;
pub mod import_bvh;
pub mod import_gltf;
pub mod maya;
pub mod mesh_file;
pub mod obj;
pub mod retarget;
pub mod retarget_feet;
mod retarget_map;
pub mod rig_builder;
pub mod runtime_view;
pub mod scene;
pub mod weights_file;

pub use bvh::{parse_bvh, Bvh, BvhError};
pub use gltf_read::{read_gltf, read_gltf_slice};
pub use gltf_write::{write_glb, write_gltf_embedded};
pub use scene::{GltfError, Scene};

#[cfg(test)]
mod tests;
