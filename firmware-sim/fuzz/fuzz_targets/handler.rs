//! The request handler behind valid framing: each length-prefixed body of the input is
//! given its CRC and COBS and fed byte by byte to `Server::push_byte` (the QEMU images'
//! entry point), so every body postcard accepts is executed. Every reply must be a valid
//! frame; no input may panic the firmware.
#![no_main]
use libfuzzer_sys::fuzz_target;
use maglev_firmware_fuzz::{bodies, check_reply, frame_body};
use maglev_firmware_sim::protocol::MAX_FRAME;
use maglev_firmware_sim::server::Server;

fuzz_target!(|data: &[u8]| {
    let mut server = Server::new();
    let mut out = [0u8; MAX_FRAME];
    for body in bodies(data) {
        let Some(frame) = frame_body(body) else {
            continue;
        };
        let mut replies = 0;
        for &b in &frame {
            if let Some(n) = server.push_byte(b, &mut out) {
                check_reply(&out[..n]);
                replies += 1;
            }
        }
        assert_eq!(replies, 1, "one reply per frame");
        // The board's control timer runs between requests (link-loss watchdog).
        let _ = server.timer_tick();
    }
});
