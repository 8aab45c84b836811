//! Rays and ray-primitive intersection, counter-based random numbers, Sobol points and the
//! warps from uniform numbers to directions and points; each has a WGSL twin beside it.

pub mod geometry;
pub mod rng;
pub mod sampling;
pub mod sobol;
