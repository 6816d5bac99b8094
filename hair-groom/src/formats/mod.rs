//! File formats of the guide level, one module per format; each reads (and, where it applies,
//! writes) one format and converts it to meters, Z up.

pub mod obj;
