//! Supervision: what the firmware checks every tick and how it reacts.
//!
//! | condition                         | detected by                              | reaction |
//! |-----------------------------------|------------------------------------------|----------|
//! | out-of-range sensor (open, beyond) | code = full scale                        | hold the last good sample; after `hold_ticks` bad ticks in a row: fault |
//! | stuck sensor                      | the same code `stuck_ticks` ticks in a row | as out-of-range |
//! | collision / contact               | code = 0 (gap at or below the sensor's zero) | fault at once (no hold) |
//! | SPI error                          | the bus returned an error                | as out-of-range |
//! | link lost                          | no `Step` for more than `watchdog_ticks` timer periods | fault at once |
//! | fault                              | any of the above escalated               | all coils: voltage ramps linearly from its last value to 0 over `ramp_ticks`, then stays at 0 V (the vehicle lands on its skids); latched until the next `Config` |
//!
//! Link faults (lost, late or corrupted frames) are handled by the protocol (see
//! [`crate::protocol`] and [`crate::server`]): retransmission with the same sequence number,
//! answered from the reply cache. In lockstep the firmware has no wall clock, so a lost
//! frame can never starve a control tick; the host bounds retries and reports. A board with
//! a control timer calls [`crate::server::Server::timer_tick`] every period: more than
//! `watchdog_ticks` periods without a `Step` raise [`Event::LINK_LOST`] and start the fault
//! reaction (latched like any other fault).
//!
//! Every event is raised in the step's [`crate::protocol::Reply::events`], which the host
//! logs (`events.csv`) with the step's time.

/// Event bits (several per step).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Event(pub u16);

impl Event {
    pub const CONTACT: Event = Event(1);
    pub const OUT_OF_RANGE: Event = Event(2);
    pub const STUCK: Event = Event(4);
    /// A held (substituted) sample was used.
    pub const HOLD: Event = Event(8);
    /// Entered the fault ramp in this step.
    pub const FAULT: Event = Event(16);
    /// The law's supply-voltage bound was active.
    pub const VOLTAGE_SATURATED: Event = Event(32);
    /// The law held the current at zero.
    pub const CURRENT_CLAMPED: Event = Event(64);
    /// Arithmetic saturated.
    pub const OVERFLOW: Event = Event(128);
    /// The commanded voltage exceeded the H-bridge's range and was clipped.
    pub const PWM_CLIPPED: Event = Event(256);
    pub const SPI_ERROR: Event = Event(512);
    /// The gap loop's reference `x_ref` was limited to `±x_ref_max`.
    pub const REFERENCE_LIMITED: Event = Event(1024);
    /// No `Step` for more than `watchdog_ticks` control periods: the link is lost.
    pub const LINK_LOST: Event = Event(2048);

    /// Names of the bits, for logs.
    pub const NAMES: [(Event, &'static str); 12] = [
        (Event::CONTACT, "contact"),
        (Event::OUT_OF_RANGE, "out_of_range"),
        (Event::STUCK, "stuck"),
        (Event::HOLD, "hold"),
        (Event::FAULT, "fault"),
        (Event::VOLTAGE_SATURATED, "voltage_saturated"),
        (Event::CURRENT_CLAMPED, "current_clamped"),
        (Event::OVERFLOW, "overflow"),
        (Event::PWM_CLIPPED, "pwm_clipped"),
        (Event::SPI_ERROR, "spi_error"),
        (Event::REFERENCE_LIMITED, "reference_limited"),
        (Event::LINK_LOST, "link_lost"),
    ];

    pub fn contains(self, e: Event) -> bool {
        self.0 & e.0 == e.0
    }
    pub fn raise(&mut self, e: Event) {
        self.0 |= e.0;
    }
}

/// Operating mode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(u8)]
pub enum Mode {
    /// Levitation control running.
    #[default]
    Normal = 0,
    /// Fault: coil voltages ramping to zero.
    Ramp = 1,
    /// Fault: coils at 0 V.
    Off = 2,
}

impl Mode {
    pub fn from_u8(v: u8) -> Option<Mode> {
        match v {
            0 => Some(Mode::Normal),
            1 => Some(Mode::Ramp),
            2 => Some(Mode::Off),
            _ => None,
        }
    }
}

/// Limits, in control ticks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    pub hold_ticks: u16,
    pub stuck_ticks: u16,
    pub ramp_ticks: u16,
}

/// Per-channel sensor bookkeeping.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SensorState {
    pub last_good: u16,
    pub last_raw: u16,
    pub repeats: u16,
    pub bad_run: u16,
}

/// The verdict on one raw sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Verdict {
    /// The code to control with (the raw one, or the held last good one).
    pub code: u16,
    pub events: Event,
    /// Escalate to the fault ramp now.
    pub fault: bool,
}

/// Checks one raw code against the limits and updates the channel's bookkeeping.
pub fn check(s: &mut SensorState, raw: Option<u16>, full_scale: u16, lim: &Limits) -> Verdict {
    let mut events = Event::default();
    let Some(raw) = raw else {
        events.raise(Event::SPI_ERROR);
        return bad(s, events, lim);
    };
    if raw == s.last_raw {
        s.repeats = s.repeats.saturating_add(1);
    } else {
        s.repeats = 0;
    }
    s.last_raw = raw;
    if raw == 0 {
        events.raise(Event::CONTACT);
        s.bad_run = s.bad_run.saturating_add(1);
        return Verdict {
            code: raw,
            events,
            fault: true,
        };
    }
    if raw >= full_scale {
        events.raise(Event::OUT_OF_RANGE);
        return bad(s, events, lim);
    }
    if lim.stuck_ticks > 0 && s.repeats >= lim.stuck_ticks {
        events.raise(Event::STUCK);
        return bad(s, events, lim);
    }
    s.bad_run = 0;
    s.last_good = raw;
    Verdict {
        code: raw,
        events,
        fault: false,
    }
}

fn bad(s: &mut SensorState, mut events: Event, lim: &Limits) -> Verdict {
    s.bad_run = s.bad_run.saturating_add(1);
    events.raise(Event::HOLD);
    Verdict {
        code: s.last_good,
        events,
        // `bad_run` saturates: at its maximum it escalates whatever `hold_ticks` says, so no
        // limit can turn escalation off (the Config check bounds hold_ticks anyway).
        fault: s.bad_run > lim.hold_ticks || s.bad_run == u16::MAX,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIM: Limits = Limits {
        hold_ticks: 3,
        stuck_ticks: 5,
        ramp_ticks: 10,
    };

    #[test]
    fn out_of_range_holds_then_faults() {
        let mut s = SensorState::default();
        assert!(!check(&mut s, Some(100), 4095, &LIM).fault);
        for k in 1..=3 {
            let v = check(&mut s, Some(4095), 4095, &LIM);
            assert_eq!(v.code, 100, "held at tick {k}");
            assert!(v.events.contains(Event::OUT_OF_RANGE) && !v.fault);
        }
        assert!(check(&mut s, Some(4095), 4095, &LIM).fault);
    }

    #[test]
    fn recovery_resets_the_hold_count() {
        let mut s = SensorState::default();
        check(&mut s, Some(100), 4095, &LIM);
        for _ in 0..3 {
            check(&mut s, Some(4095), 4095, &LIM);
        }
        assert!(!check(&mut s, Some(101), 4095, &LIM).fault);
        for _ in 0..3 {
            assert!(!check(&mut s, Some(4095), 4095, &LIM).fault);
        }
    }

    #[test]
    fn stuck_code_is_detected_after_the_limit() {
        let mut s = SensorState::default();
        for k in 0..=5 {
            let v = check(&mut s, Some(200), 4095, &LIM);
            assert_eq!(v.events.contains(Event::STUCK), k == 5, "tick {k}");
        }
    }

    #[test]
    fn contact_faults_at_once_and_spi_error_holds() {
        let mut s = SensorState::default();
        check(&mut s, Some(100), 4095, &LIM);
        let v = check(&mut s, None, 4095, &LIM);
        assert!(v.events.contains(Event::SPI_ERROR) && !v.fault && v.code == 100);
        let v = check(&mut s, Some(0), 4095, &LIM);
        assert!(v.events.contains(Event::CONTACT) && v.fault);
    }
}
