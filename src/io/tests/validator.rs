//! glTF reader tests.
