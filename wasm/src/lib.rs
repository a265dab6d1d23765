//! WebAssembly front end (being written).
