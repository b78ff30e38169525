#![no_std]

pub mod board;
