//! A host byte stream (`std::io`: stdin/stdout, a serial device, a socket) as the
//! `embedded-io` port of [`crate::server::serve`], so the host process and the tests run the
//! boards' own loop. Host only.

use std::io::ErrorKind;

/// A reader and a writer as one `embedded-io` port. A read that is interrupted or times out
/// (a serial port's read timeout) is retried: only data, the end or an error returns.
pub struct StdPort<R, W> {
    pub reader: R,
    pub writer: W,
}

/// A `std::io` error as an `embedded-io` one.
#[derive(Debug)]
pub struct IoError(pub std::io::Error);

impl embedded_io::Error for IoError {
    fn kind(&self) -> embedded_io::ErrorKind {
        embedded_io::ErrorKind::Other
    }
}

impl<R, W> embedded_io::ErrorType for StdPort<R, W> {
    type Error = IoError;
}

impl<R: std::io::Read, W> embedded_io::Read for StdPort<R, W> {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, IoError> {
        loop {
            match self.reader.read(buf) {
                Err(e) if matches!(e.kind(), ErrorKind::Interrupted | ErrorKind::TimedOut) => {}
                r => return r.map_err(IoError),
            }
        }
    }
}

impl<R, W: std::io::Write> embedded_io::Write for StdPort<R, W> {
    fn write(&mut self, buf: &[u8]) -> Result<usize, IoError> {
        self.writer.write(buf).map_err(IoError)
    }

    fn flush(&mut self) -> Result<(), IoError> {
        self.writer.flush().map_err(IoError)
    }
}
