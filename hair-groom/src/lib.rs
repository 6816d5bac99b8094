//! # hair-groom
