//! Placeholder for the numerics study (filled in below).
