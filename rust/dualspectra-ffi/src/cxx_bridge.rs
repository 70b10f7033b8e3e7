//! cxx bridge (in progress).
