//! hairsys CLI library
