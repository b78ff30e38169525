//! `maglev hil SCENARIO --firmware inproc|process|qemu|serial:PATH [--baud N] [--realtime]
//! [--set key=value]... [--out DIR] [--compare]`: a passage with the levitation firmware as
//! the controller.

use crate::cli::progress::Progress;
use crate::hil::compare::{compare, Comparison};
use crate::hil::coupling::EventRecord;
use crate::hil::link::{InProc, Link, LinkFaults, LinkStats, StreamLink};
use crate::hil::realtime::{Paced, RealtimeStats, WallClock};
use crate::hil::{HilSettings, HIL_KEYS};
use crate::output::{response_recorder, write_run, Columns, Staging, Summary};
use crate::probes::Tee;
use crate::setup::simulate;
use crate::simulation::magnets::CoreMagnets;
use crate::{Error, Result};
use maglev_firmware_sim::supervision::Event;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FirmwareMode {
    /// The firmware's server called directly (no bytes).
    Inproc,
    /// The `maglev-firmware` program over its stdin/stdout.
    Process,
    /// The QEMU image (mps2-an386, Cortex-M4) over its serial port.
    Qemu,
    /// A serial device (a board's UART or USB CDC port, or a pty): `serial:PATH`.
    Serial(String),
}

impl FirmwareMode {
    /// The name in summary.json.
    pub fn name(&self) -> &'static str {
        match self {
            FirmwareMode::Inproc => "inproc",
            FirmwareMode::Process => "process",
            FirmwareMode::Qemu => "qemu",
            FirmwareMode::Serial(_) => "serial",
        }
    }
}

impl std::str::FromStr for FirmwareMode {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "inproc" => Ok(FirmwareMode::Inproc),
            "process" => Ok(FirmwareMode::Process),
            "qemu" => Ok(FirmwareMode::Qemu),
            _ => match s.strip_prefix("serial:") {
                Some(path) if !path.is_empty() => Ok(FirmwareMode::Serial(path.into())),
                _ => Err(format!(
                    "expected inproc, process, qemu or serial:PATH, got `{s}`"
                )),
            },
        }
    }
}

/// How the QEMU image talks to the host; the host sees QEMU's stdin/stdout either way.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum QemuLink {
    /// UART0 of mps2-an386 on `-serial stdio` (image `qemu-m4-server`): the board's own port,
    /// as on hardware; QEMU moves it one byte per I/O-thread/vCPU hand-over (~150 exchanges/s).
    Uart,
    /// Semihosting reads and writes of the host's /dev/stdin and /dev/stdout (image
    /// `qemu-m4-server-semi`): whole frames per trap, at the firmware's speed under QEMU.
    Semihosting,
}

impl QemuLink {
    /// The image built for this link (`firmware-sim/src/bin/`).
    pub fn image_name(self) -> &'static str {
        match self {
            QemuLink::Uart => "qemu-m4-server",
            QemuLink::Semihosting => "qemu-m4-server-semi",
        }
    }
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// A scenario TOML file with a Fig. 1 vehicle, or a bundled name (paper-4.2).
    pub scenario: String,
    /// inproc, process, qemu, or serial:PATH (a serial device: a board, or a pty).
    #[arg(long, default_value = "inproc", value_parser = clap::value_parser!(FirmwareMode))]
    pub firmware: FirmwareMode,
    /// The baud rate of `--firmware serial:PATH` (8N1, raw; default 115200). Refused with any
    /// other mode, which has no serial line to set.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub baud: Option<u32>,
    /// Pace each host step to the wall clock (one control period of Δt each); report deadline
    /// misses and exchange latency in summary.json, and stop with an error when the link is
    /// too slow for the rate (docs/hil.md, "Real time").
    #[arg(long)]
    pub realtime: bool,
    /// Scenario keys as for `maglev run`, plus firmware keys: rate, delay, scalar (i4f28|f32),
    /// adc_bits, adc_lsb, adc_offset, adc_noise (LSB rms), adc_seed, pwm_bits, v_dc,
    /// hold_ticks, stuck_ticks, ramp_ticks, fault=stuck|range|contact:CHANNEL@SECONDS,
    /// link_fault=corrupt|corrupt_reply|drop|late:EVERY (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Also run the ideal in-process core run and report the differences.
    #[arg(long)]
    pub compare: bool,
    /// The firmware program for `--firmware process` [default: $MAGLEV_FIRMWARE, or
    /// `maglev-firmware` next to this program].
    #[arg(long)]
    pub firmware_bin: Option<PathBuf>,
    /// The QEMU image for `--firmware qemu` [default: $MAGLEV_QEMU_IMAGE, or the link's image
    /// in TARGET/thumbv7em-none-eabihf/release/, TARGET being the target directory this
    /// program was built in].
    #[arg(long)]
    pub qemu_image: Option<PathBuf>,
    /// The link to the QEMU image: UART0 (as on the board) or semihosting (fast).
    #[arg(long, value_enum, default_value = "uart")]
    pub qemu_link: QemuLink,
    /// The QEMU program [default: $MAGLEV_QEMU, or qemu-system-arm].
    #[arg(long)]
    pub qemu: Option<PathBuf>,
    /// Reply timeout before a retransmission (ms).
    #[arg(long, default_value_t = 5000)]
    pub timeout_ms: u64,
    /// Retransmissions before giving up.
    #[arg(long, default_value_t = 5)]
    pub retries: u32,
}

/// `summary.json` of a HIL run: the `maglev run` summary plus the firmware's figures.
#[derive(Serialize, Debug)]
pub struct HilSummary {
    #[serde(flatten)]
    pub run: Summary,
    pub firmware: String,
    /// The QEMU link (`uart` or `semihosting`) of `--firmware qemu`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub qemu_link: Option<String>,
    pub scalar: String,
    pub rate_hz: u32,
    pub ticks_per_step: u32,
    pub delay: bool,
    /// Round trips (Config, Step, Commit) per second of time spent in the link.
    pub exchanges_per_second: f64,
    /// Round trips per second of the whole run's wall time (plant included).
    pub exchanges_per_wall_second: f64,
    pub link: LinkStats,
    /// The pacing figures of `--realtime`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub realtime: Option<RealtimeStats>,
    /// How many steps raised each event.
    pub events: BTreeMap<String, usize>,
    pub first_fault_s: Option<f64>,
    pub compare: Option<Comparison>,
    /// The same differences over the steps before the first fault (when there was one).
    pub compare_before_fault: Option<Comparison>,
}

fn parse_link_fault(v: &str, lf: &mut LinkFaults) -> Result<()> {
    let err = || {
        Error::invalid(
            "--set link_fault",
            format!("`{v}`: expected corrupt|corrupt_reply|drop|late:EVERY"),
        )
    };
    let (k, n) = v.split_once(':').ok_or_else(err)?;
    let n: u64 = n.parse().map_err(|_| err())?;
    match k {
        "corrupt" => lf.corrupt_request = n,
        "corrupt_reply" => lf.corrupt_reply = n,
        "drop" => lf.drop_request = n,
        "late" => lf.late_request = n,
        _ => return Err(err()),
    }
    Ok(())
}

fn firmware_program(args: &Args) -> PathBuf {
    if let Some(p) = &args.firmware_bin {
        return p.clone();
    }
    if let Some(p) = std::env::var_os("MAGLEV_FIRMWARE") {
        return p.into();
    }
    let exe = std::env::current_exe().unwrap_or_default();
    exe.with_file_name(format!("maglev-firmware{}", std::env::consts::EXE_SUFFIX))
}

/// The default QEMU image of a link: `TARGET/thumbv7em-none-eabihf/release/NAME`, where
/// TARGET is the target directory of this program (`TARGET/release/maglev`), so a workspace
/// build finds the image that `cargo build --target thumbv7em-none-eabihf` put beside it.
pub fn default_qemu_image(link: QemuLink) -> Option<PathBuf> {
    let exe = std::env::current_exe().ok()?;
    let target = exe.parent()?.parent()?;
    Some(
        target
            .join("thumbv7em-none-eabihf")
            .join("release")
            .join(link.image_name()),
    )
}

/// The QEMU command line for an image; the link is on QEMU's stdin/stdout. No `-icount`: the
/// guest runs as fast as QEMU can translate it (instruction counting is for the self-tests).
///
/// * `uart`: UART0 on a plain `-serial stdio` (explicit `-monitor none`, so `-nographic`'s
///   `mon:stdio` mux, which eats 0x01 bytes, is not used).
/// * `semihosting`: `-serial null`, so that only the image (through semihosting) reads stdin.
pub fn qemu_command(qemu: &Path, image: &Path, link: QemuLink) -> Command {
    let serial = match link {
        QemuLink::Uart => "stdio",
        QemuLink::Semihosting => "null",
    };
    let mut c = Command::new(qemu);
    c.args([
        "-machine",
        "mps2-an386",
        "-cpu",
        "cortex-m4",
        "-nographic",
        "-monitor",
        "none",
        "-serial",
        serial,
        "-semihosting-config",
        "enable=on,target=native",
        "-kernel",
    ])
    .arg(image);
    c
}

/// Opens the link of a mode: a link fault without bytes is `Invalid` on `--set link_fault`,
/// a missing program or image and a failed start are [`Error::Firmware`].
pub fn open_link(args: &Args, faults: LinkFaults) -> Result<Box<dyn Link>> {
    if args.baud.is_some() && !matches!(args.firmware, FirmwareMode::Serial(_)) {
        return Err(Error::invalid(
            "--baud",
            "sets a serial line: only with --firmware serial:PATH",
        ));
    }
    let mut link = match &args.firmware {
        FirmwareMode::Inproc => {
            if faults != LinkFaults::default() {
                return Err(Error::invalid(
                    "--set link_fault",
                    "needs --firmware process, qemu or serial:PATH (in-process has no bytes)",
                ));
            }
            return Ok(Box::new(InProc::default()));
        }
        FirmwareMode::Process => {
            let prog = firmware_program(args);
            if !prog.exists() {
                return Err(Error::Firmware(format!(
                    "program {} not found: build it (cargo build -p maglev-firmware-sim \
                     --bin maglev-firmware --release) or pass --firmware-bin / $MAGLEV_FIRMWARE",
                    prog.display()
                )));
            }
            StreamLink::spawn(Command::new(prog))?
        }
        FirmwareMode::Qemu => {
            let name = args.qemu_link.image_name();
            let build = format!(
                "build it with `cargo build --release -p maglev-firmware-sim --target \
                 thumbv7em-none-eabihf --bin {name}` (after `rustup target add \
                 thumbv7em-none-eabihf`), or pass --qemu-image PATH / $MAGLEV_QEMU_IMAGE"
            );
            let image = args
                .qemu_image
                .clone()
                .or_else(|| std::env::var_os("MAGLEV_QEMU_IMAGE").map(PathBuf::from))
                .or_else(|| default_qemu_image(args.qemu_link))
                .ok_or_else(|| Error::Firmware(format!("no QEMU image {name}: {build}")))?;
            if !image.exists() {
                return Err(Error::Firmware(format!(
                    "QEMU image {} not found: {build}",
                    image.display()
                )));
            }
            let qemu = args
                .qemu
                .clone()
                .or_else(|| std::env::var_os("MAGLEV_QEMU").map(PathBuf::from))
                .unwrap_or_else(|| "qemu-system-arm".into());
            StreamLink::spawn(qemu_command(&qemu, &image, args.qemu_link))?
        }
        FirmwareMode::Serial(path) => StreamLink::serial(path, args.baud.unwrap_or(115_200))?,
    };
    link.timeout = Duration::from_millis(args.timeout_ms);
    link.max_retries = args.retries;
    link.faults = faults;
    Ok(Box::new(link))
}

fn event_counts(events: &[EventRecord]) -> (BTreeMap<String, usize>, Option<f64>) {
    let mut m = BTreeMap::new();
    let mut first = None;
    for e in events {
        for (bit, name) in Event::NAMES {
            if e.events.contains(bit) {
                *m.entry(name.to_string()).or_insert(0) += 1;
            }
        }
        if e.events.contains(Event::FAULT) && first.is_none() {
            first = Some(e.t);
        }
    }
    (m, first)
}

fn events_csv(events: &[EventRecord]) -> String {
    let mut s = String::from("t,mode,events\n");
    for e in events {
        let names: Vec<&str> = Event::NAMES
            .iter()
            .filter(|(b, _)| e.events.contains(*b))
            .map(|(_, n)| *n)
            .collect();
        s.push_str(&format!("{},{},{}\n", e.t, e.mode, names.join(" ")));
    }
    s
}

pub fn run(args: Args) -> anyhow::Result<()> {
    Ok(run_inner(args)?)
}

fn run_inner(args: Args) -> Result<()> {
    let mut hs = HilSettings::default();
    let mut faults = LinkFaults::default();
    let mut scenario_sets = Vec::new();
    for s in &args.sets {
        let (k, v) = s
            .split_once('=')
            .ok_or_else(|| Error::invalid(format!("--set `{s}`"), "expected KEY=VALUE"))?;
        if k == "link_fault" {
            parse_link_fault(v, &mut faults)?;
        } else if HIL_KEYS.contains(&k) {
            hs.set(k, v)?;
        } else {
            scenario_sets.push(s.clone());
        }
    }
    let case = crate::studies::design::load(&args.scenario, &scenario_sets)?;
    if let Some(&(k, _)) = case.probes.ground_columns().first() {
        return Err(Error::invalid(
            "output.probes",
            format!(
                "`{}`: maglev hil does not compute the ground; use maglev run",
                case.probes.names[k]
            ),
        ));
    }
    let out = Staging::new(&args.out)?;
    let mut rec = response_recorder(&out, case.probes.clone())?;
    let mut link = open_link(&args, faults)?;
    let mut paced = None;
    let link_used: &mut dyn Link = if args.realtime {
        paced.insert(Paced::new(link.as_mut(), case.dt, WallClock::default()))
    } else {
        link.as_mut()
    };
    let mut bar = Progress::run("hil");
    // With --compare, the HIL run's compared histories are kept in memory too.
    let mut hil_rows = crate::hil::compare::recorder();
    let outcome = if args.compare {
        let mut both = Tee(&mut rec, &mut hil_rows);
        crate::hil::simulate(&case, &hs, link_used, &mut both, &mut |f| bar.fraction(f))?
    } else {
        crate::hil::simulate(&case, &hs, link_used, &mut rec, &mut |f| bar.fraction(f))?
    };
    let wall = outcome.wall;
    drop(bar);
    rec.finish()?;
    let realtime = paced.map(|p| p.finish()).transpose()?;
    let stats = link.stats();
    drop(link);
    let (events, first_fault_s) = event_counts(&outcome.events);
    let (cmp, cmp_before) = if args.compare {
        let mut bar = Progress::run("hil: ideal run");
        let mut ideal = crate::hil::compare::recorder();
        simulate(&case, &mut CoreMagnets::new(), &mut ideal, &mut |f| {
            bar.fraction(f)
        })?;
        drop(bar);
        let all = compare(&hil_rows, &ideal, None)?;
        let before = match first_fault_s {
            Some(tf) => Some(compare(&hil_rows, &ideal, Some(tf))?),
            None => None,
        };
        (Some(all), before)
    } else {
        (None, None)
    };
    let columns = Columns::read(&out)?;
    let run = Summary::new(&args.scenario, &case, &outcome.outcome, wall, &columns);
    let summary = HilSummary {
        firmware: args.firmware.name().to_string(),
        qemu_link: (args.firmware == FirmwareMode::Qemu)
            .then(|| format!("{:?}", args.qemu_link).to_lowercase()),
        scalar: format!("{:?}", hs.scalar).to_lowercase(),
        rate_hz: hs.rate_hz,
        ticks_per_step: (case.dt * hs.rate_hz as f64).round() as u32,
        delay: hs.delay,
        exchanges_per_second: stats.exchanges as f64 / stats.seconds.max(1e-12),
        exchanges_per_wall_second: stats.exchanges as f64 / wall.max(1e-12),
        link: stats,
        realtime,
        events,
        first_fault_s,
        compare: cmp,
        compare_before_fault: cmp_before,
        run,
    };
    write_run(&out, &outcome.outcome, &summary.run, &args.sets, &columns)?;
    let put = |name: &str, text: String| out.put(name, &text);
    put(
        "summary.json",
        serde_json::to_string_pretty(&summary).map_err(|e| Error::numerical(e.to_string()))? + "\n",
    )?;
    put("events.csv", events_csv(&outcome.events))?;
    out.finish()?;
    crate::cli::run::warn(&outcome.outcome);
    eprintln!(
        "maglev: hil ({}) {} steps, {:.3} s simulated in {:.2} s wall; {} exchanges, {:.0}/s in the link \
         ({} retries); wrote {}",
        summary.firmware,
        summary.run.steps,
        summary.run.simulated_seconds,
        wall,
        stats.exchanges,
        summary.exchanges_per_second,
        stats.retries,
        args.out.display()
    );
    if let Some(t) = first_fault_s {
        eprintln!("maglev: firmware fault at t = {t} s (see events.csv)");
    }
    crate::cli::stdout::print(&compare_tables(&summary))?;
    crate::cli::run::check_converged(&outcome.outcome)
}

/// The `--compare` tables printed on stdout (empty without `--compare`).
fn compare_tables(summary: &HilSummary) -> String {
    let tables = [
        ("whole run", &summary.compare),
        ("before the first fault", &summary.compare_before_fault),
    ];
    let mut text = String::new();
    for (label, c) in tables {
        let Some(c) = c else { continue };
        text += &format!("difference to the ideal run, {label} (max |HIL − ideal|):\n");
        for (name, d) in [
            ("midspan_z (m)", c.midspan_z),
            ("wheel1_gap_z (m)", c.wheel1_gap_z),
            ("wheel1_force_z (N)", c.wheel1_force_z),
        ] {
            text += &format!(
                "  {name:20} {:.4e} at t = {:.4} s  ({:.2} % of the ideal peak {:.4e})\n",
                d.max_abs,
                d.at_t,
                100.0 * d.relative,
                d.ideal_peak
            );
        }
    }
    text
}
