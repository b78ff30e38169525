//! The frame decoder and the frame reader on arbitrary bytes: never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use maglev_firmware_sim::protocol::{self, Envelope, FrameReader, Request, Response};

fuzz_target!(|data: &[u8]| {
    let _ = protocol::decode::<Request>(data);
    let _ = protocol::decode::<Response>(data);
    // As a byte stream: every frame the reader hands out goes through the decoder, and a
    // request that decodes must encode again.
    let mut reader = FrameReader::new();
    let mut buf = [0u8; protocol::MAX_FRAME];
    for &b in data {
        if let Some(Ok(frame)) = reader.push(b) {
            if let Ok(env) = protocol::decode::<Request>(frame) {
                let env: Envelope<Request> = env;
                let n = protocol::encode(&env, &mut buf).expect("a decoded request re-encodes");
                let again: Envelope<Request> =
                    protocol::decode(&buf[..n - 1]).expect("and decodes again");
                assert_eq!(again, env);
            }
        }
    }
});
