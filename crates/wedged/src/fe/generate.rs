//! Built-in meshes of the standard test bodies (to be written).
