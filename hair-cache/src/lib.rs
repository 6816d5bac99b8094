//! # hair-cache
