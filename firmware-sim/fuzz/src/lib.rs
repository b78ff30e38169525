//! What the two fuzz targets share: how an input becomes a sequence of request bodies, and
//! the checks every reply must pass.
//!
//! * `decode`: the input is one received frame (and, byte by byte, a stream): the decoders
//!   and the frame reader must reject or accept it without panicking.
//! * `handler`: the input is a sequence of postcard bodies, each preceded by its length
//!   (u16, little endian). The harness appends the CRC and COBS-encodes each body
//!   ([`frame_body`]), so every body that postcard accepts reaches `Server::handle` — a
//!   random frame would almost never pass the CRC. Every reply must be one valid frame
//!   carrying a `Response`.
use maglev_firmware_sim::protocol::{self, Envelope, Response, MAX_FRAME};

const CRC: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC);

/// Splits `data` into length-prefixed bodies (a short or truncated tail is one last body).
pub fn bodies(mut data: &[u8]) -> impl Iterator<Item = &[u8]> {
    core::iter::from_fn(move || {
        if data.is_empty() {
            return None;
        }
        if data.len() < 2 {
            let b = data;
            data = &[];
            return Some(b);
        }
        let n = u16::from_le_bytes([data[0], data[1]]) as usize;
        let rest = &data[2..];
        let n = n.min(rest.len());
        let (b, tail) = rest.split_at(n);
        data = tail;
        Some(b)
    })
}

/// `COBS(body ‖ crc32_le(body)) ‖ 0x00`, the wire form of a body; `None` if too long.
pub fn frame_body(body: &[u8]) -> Option<Vec<u8>> {
    let mut raw = body.to_vec();
    raw.extend_from_slice(&CRC.checksum(body).to_le_bytes());
    let mut out = vec![0u8; cobs::max_encoding_length(raw.len()) + 1];
    let k = cobs::encode(&raw, &mut out);
    out.truncate(k);
    out.push(0);
    (out.len() <= MAX_FRAME).then_some(out)
}

/// A reply frame (delimiter included) must decode to a `Response`.
pub fn check_reply(frame: &[u8]) {
    assert!(!frame.is_empty(), "the server always answers a frame");
    assert_eq!(frame.last(), Some(&0), "delimited");
    let env: Envelope<Response> =
        protocol::decode(&frame[..frame.len() - 1]).expect("reply decodes");
    assert_eq!(env.version, protocol::VERSION);
}
