//! The frames between a pvfc drive and its host over a serial line (hardware in the loop).
//!
//! Once a control period the host sends a [`Sense`] (a sequence number, the encoders' counts,
//! an operator's command if any) and the drive answers with an [`Actuate`] (the same sequence
//! number, the torque for the motors, the drive's state). On the wire each message is:
//!
//! `COBS( postcard(message) ‖ CRC-16/IBM-SDLC(postcard(message)) ) ‖ 0x00`
//!
//! postcard gives a compact, stable encoding (varints); the CRC detects every error of up to
//! three bits and every burst of up to sixteen in a frame of this size; COBS leaves no 0 byte
//! inside a frame, so the 0 that ends it is where a receiver that lost bytes resynchronises.
//! [`encode`] writes a frame into a buffer; a [`Decoder`] takes bytes one at a time (as a
//! UART's receive interrupt gets them) and yields each frame's message or its error. Missed
//! or repeated frames are the application's to see, from the sequence numbers.
//!
//! `no_std`, no allocation: messages carry at most [`MAX_JOINTS`] joints, frames are at most
//! [`MAX_FRAME`] bytes.
#![no_std]

use heapless::Vec;
use serde::{de::DeserializeOwned, Deserialize, Serialize};

/// The most joints a message carries.
pub const MAX_JOINTS: usize = 8;

/// The longest frame on the wire, its terminating 0 included (a [`Sense`] or an [`Actuate`]
/// of [`MAX_JOINTS`] joints fits with room to spare).
pub const MAX_FRAME: usize = 96;

/// The longest message before its CRC and the stuffing.
const MAX_MESSAGE: usize = MAX_FRAME - 8;

/// CRC-16/IBM-SDLC (the X.25 CRC, polynomial 0x1021, reflected).
const CRC: crc::Crc<u16> = crc::Crc::<u16>::new(&crc::CRC_16_IBM_SDLC);

/// What an operator asks of the drive.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Command {
    /// Run the controller at the nominal speed `r` (eq. 36).
    Start(f32),
    /// Change the nominal speed `r`.
    Speed(f32),
    /// The safe torque (zero) from the next period.
    Stop,
}

/// Host → drive, once a control period.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sense {
    /// The period's number (wrapping).
    pub seq: u32,
    /// The encoders' counts, one per joint.
    pub counts: Vec<i32, MAX_JOINTS>,
    /// An operator's command, if one arrived.
    pub command: Option<Command>,
}

/// The drive's state, as it reports it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum DriveState {
    /// Stopped: the safe torque.
    Stopped,
    /// Running the controller.
    Running,
    /// A fault latched (the controller's error, by `pvfc_core::ErrorKind`'s name index, or a
    /// link error): the safe torque until reset.
    Fault(u8),
}

/// Drive → host, once a control period, in answer to the [`Sense`] of the same `seq`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Actuate {
    /// The [`Sense`]'s period number.
    pub seq: u32,
    /// The torque for each joint's motor over the period (N·m or N).
    pub torque: Vec<f32, MAX_JOINTS>,
    /// The drive's state after the period.
    pub state: DriveState,
    /// The frames the drive could not read so far (corrupted on the way, or not a [`Sense`]).
    pub errors: u32,
}

/// A frame that could not be written or read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinkError {
    /// The message does not fit a frame, or a frame ran past [`MAX_FRAME`] bytes, its 0
    /// included.
    TooLong,
    /// The bytes between two 0s are not a COBS frame.
    Stuffing,
    /// The CRC does not match: the frame was corrupted on the way.
    Crc,
    /// The CRC matches but the bytes are not a message of the expected kind.
    Message,
    /// An empty frame (two 0s in a row).
    Empty,
}

impl core::fmt::Display for LinkError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            LinkError::TooLong => "a frame longer than MAX_FRAME bytes",
            LinkError::Stuffing => "a frame that is not COBS-stuffed",
            LinkError::Crc => "a frame whose CRC does not match (corrupted)",
            LinkError::Message => "a frame that is not a message of the expected kind",
            LinkError::Empty => "an empty frame",
        })
    }
}

/// Writes `message`'s frame, its terminating 0 included, at the start of `out` (at least
/// [`MAX_FRAME`] bytes is always enough) and returns its length.
pub fn encode<M: Serialize>(message: &M, out: &mut [u8]) -> Result<usize, LinkError> {
    let mut raw = [0u8; MAX_MESSAGE];
    let n = postcard::to_slice(message, &mut raw[..MAX_MESSAGE - 2])
        .map_err(|_| LinkError::TooLong)?
        .len();
    frame(&raw[..n], out)
}

/// The room the frame of a body of `body` bytes needs, its terminating 0 included: the frame's
/// length for a body of fewer than 254 bytes, at most one byte more per 254 beyond.
pub fn frame_len(body: usize) -> usize {
    cobs::max_encoding_length(body + 2) + 1
}

/// Frames `body` as the link does (its CRC appended, the whole COBS-stuffed, then a 0) at the
/// start of `out` (at least [`frame_len`] bytes) and returns the frame's length. [`encode`]
/// frames a message's postcard bytes with it; any body can be framed, so that a test reaches
/// the message decoder behind a valid CRC (a frame longer than [`MAX_FRAME`] reads as
/// [`LinkError::TooLong`]).
pub fn frame(body: &[u8], out: &mut [u8]) -> Result<usize, LinkError> {
    let stuffed = cobs::max_encoding_length(body.len() + 2);
    if out.len() < stuffed + 1 {
        return Err(LinkError::TooLong);
    }
    let crc = CRC.checksum(body).to_le_bytes();
    let mut encoder = cobs::CobsEncoder::new(&mut out[..stuffed]);
    encoder
        .push(body)
        .and_then(|()| encoder.push(&crc))
        .map_err(|_| LinkError::TooLong)?;
    let len = encoder.finalize();
    out[len] = 0;
    Ok(len + 1)
}

/// Reads the messages of kind `M` out of a byte stream, one byte at a time.
#[derive(Clone, Debug)]
pub struct Decoder<M> {
    frame: [u8; MAX_FRAME],
    len: usize,
    /// Bytes dropped since a frame ran too long, until its 0.
    overflowed: bool,
    kind: core::marker::PhantomData<M>,
}

impl<M> Default for Decoder<M> {
    fn default() -> Self {
        Decoder {
            frame: [0; MAX_FRAME],
            len: 0,
            overflowed: false,
            kind: core::marker::PhantomData,
        }
    }
}

impl<M: DeserializeOwned> Decoder<M> {
    /// A decoder waiting for a frame.
    pub fn new() -> Self {
        Self::default()
    }

    /// Takes the next byte: `None` inside a frame; at a frame's 0, its message or why it could
    /// not be read. The decoder is ready for the next frame either way.
    pub fn push(&mut self, byte: u8) -> Option<Result<M, LinkError>> {
        if byte != 0 {
            // A frame is at most MAX_FRAME bytes with its 0: MAX_FRAME − 1 before it.
            if self.len < MAX_FRAME - 1 {
                self.frame[self.len] = byte;
                self.len += 1;
            } else {
                self.overflowed = true;
            }
            return None;
        }
        let len = core::mem::take(&mut self.len);
        if core::mem::take(&mut self.overflowed) {
            return Some(Err(LinkError::TooLong));
        }
        Some(Self::read(&mut self.frame[..len]))
    }

    fn read(frame: &mut [u8]) -> Result<M, LinkError> {
        if frame.is_empty() {
            return Err(LinkError::Empty);
        }
        let n = cobs::decode_in_place(frame).map_err(|_| LinkError::Stuffing)?;
        if n < 2 {
            return Err(LinkError::Stuffing);
        }
        let (body, crc) = frame[..n].split_at(n - 2);
        if CRC.checksum(body).to_le_bytes() != [crc[0], crc[1]] {
            return Err(LinkError::Crc);
        }
        match postcard::take_from_bytes::<M>(body) {
            Ok((message, [])) => Ok(message),
            _ => Err(LinkError::Message),
        }
    }
}
