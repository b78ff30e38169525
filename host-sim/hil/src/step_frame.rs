//! Whether one step's request fits the wire, checked before the firmware is configured: a
//! step of `ticks` control ticks carries `ticks × channels` ADC codes (and, under the state
//! law, `ticks × wheels` accelerometer codes) in one frame of at most
//! [`MAX_FRAME`] bytes. Without this check a rate the frame cannot carry was accepted and the
//! run failed at its first step with "cannot encode request 2", naming no key.

use maglev_firmware_sim::heapless::Vec;
use maglev_firmware_sim::protocol::{self, Envelope, Request, MAX_FRAME, MAX_SAMPLES, VERSION};
use maglev_sim::{Error, Result};

/// The largest step request of `ticks` ticks over `channels` channels, with `accels`
/// accelerometers (`None`: a law without them), encoded with every value at its longest
/// (postcard varints of u16::MAX and i16::MIN, no zero byte for COBS to spare): `true` when
/// it fits a frame.
fn fits(ticks: usize, channels: usize, accels: Option<usize>) -> bool {
    let (n, m) = (ticks * channels, ticks * accels.unwrap_or(0));
    if n > MAX_SAMPLES || m > MAX_SAMPLES {
        return false;
    }
    let codes: Vec<u16, MAX_SAMPLES> = core::iter::repeat_n(u16::MAX, n).collect();
    let msg = match accels {
        None => Request::Step {
            step: u32::MAX,
            codes,
        },
        Some(_) => Request::StepAccel {
            step: u32::MAX,
            codes,
            wired: u16::MAX,
            accel: core::iter::repeat_n(i16::MIN, m).collect(),
        },
    };
    let env = Envelope {
        version: VERSION,
        seq: u32::MAX,
        msg,
    };
    protocol::encode(&env, &mut [0u8; MAX_FRAME]).is_ok()
}

/// `Ok` when a step of `ticks` ticks fits one frame ([`fits`]), else one line naming `rate`
/// and `run.dt_s` with the most ticks per step that fit here.
pub fn check(ticks: usize, channels: usize, accels: Option<usize>) -> Result<()> {
    if fits(ticks, channels, accels) {
        return Ok(());
    }
    let most = (1..ticks)
        .rev()
        .find(|&t| fits(t, channels, accels))
        .unwrap_or(0);
    let what = match accels {
        Some(w) => format!("{channels} magnet channels and {w} accelerometers"),
        None => format!("{channels} magnet channels"),
    };
    Err(Error::invalid(
        "--set rate",
        format!(
            "gives {ticks} control ticks per step (run.dt_s × rate), whose samples for {what} \
             do not fit one {MAX_FRAME}-byte frame of the protocol: at most {most} ticks per \
             step here (lower the rate or run.dt_s)"
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bound is the encoder's own: the largest accepted tick count encodes and the next
    /// does not, with and without accelerometers (12 channels: the Fig. 1 car).
    #[test]
    fn the_largest_accepted_step_encodes_and_the_next_is_refused() {
        for accels in [None, Some(4)] {
            let most = (1..=MAX_SAMPLES)
                .take_while(|&t| fits(t, 12, accels))
                .count();
            assert!(most > 0 && most < MAX_SAMPLES);
            check(most, 12, accels).unwrap();
            let e = check(most + 1, 12, accels).unwrap_err().to_string();
            assert!(
                e.starts_with("--set rate: gives")
                    && e.contains(&format!("at most {most} ticks per step"))
                    && !e.contains('\n'),
                "{e}"
            );
        }
        // 100 kHz at Δt = 1 ms under the state law: 100 ticks, refused.
        assert!(check(100, 12, Some(4)).is_err());
        check(10, 12, Some(4)).unwrap();
    }
}
