//! Unit tests of the closed forms (filled below).
