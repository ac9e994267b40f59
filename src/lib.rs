//! ffr
