#![no_std]
//! Levitation firmware for the magnets of one EMS maglev vehicle, and its simulated board.
//!
//! * [`firmware`]: the control loop, generic over embedded-hal 1.0 (`SpiDevice` ADC,
//!   `SetDutyCycle` H-bridges) and over the core's scalar type.
//! * [`adc`], [`hbridge`]: the simulated converter chip and power stage.
//! * [`accel`]: the magnet's accelerometer on SPI (driver, simulated part; state law).
//! * [`guide`]: the guidance pairs under the core's guidance law (`Config::guidance`).
//! * [`supervision`]: sensor checks and the fault reactions.
//! * [`protocol`]: the framed wire format (postcard + CRC-32 + COBS, sequence numbers).
//! * [`server`]: executes protocol requests on the firmware (step / commit / reply cache);
//!   the same code runs in-process on the host, as a host process and in the QEMU image;
//!   [`server::serve`] is the serial server loop of every byte-stream board.
//! * `host_io` (host only): `std::io` streams as that loop's `embedded-io` port.
//!
//! Everything is `no_std` and allocation-free; see `docs/hil.md` for the timing model.

#[cfg(not(target_os = "none"))]
extern crate std;

pub use heapless;

pub mod accel;
pub mod adc;
pub mod firmware;
pub mod guide;
pub mod hbridge;
pub mod protocol;
pub mod server;
pub mod supervision;
pub mod validate;

pub mod board;
#[cfg(not(target_os = "none"))]
pub mod host_io;
