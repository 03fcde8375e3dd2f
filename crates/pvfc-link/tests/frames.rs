//! The frames of pvfc-link: what is sent is what is read, a corrupted frame is never read as
//! a message, and a receiver finds the next frame after any garbage.

use proptest::prelude::*;
use pvfc_link::{
    encode, frame_len, Actuate, Command, Decoder, DriveState, LinkError, Sense, MAX_FRAME,
    MAX_JOINTS,
};

fn sense(seq: u32, counts: &[i32], command: Option<Command>) -> Sense {
    Sense {
        seq,
        counts: counts.iter().copied().collect(),
        command,
    }
}

fn frame<M: serde::Serialize>(message: &M) -> Vec<u8> {
    let mut out = [0u8; MAX_FRAME];
    let n = encode(message, &mut out).unwrap();
    out[..n].to_vec()
}

/// Every result a decoder yields over `bytes`.
fn read_all<M: serde::de::DeserializeOwned>(bytes: &[u8]) -> Vec<Result<M, LinkError>> {
    let mut d = Decoder::<M>::new();
    bytes.iter().filter_map(|b| d.push(*b)).collect()
}

fn command() -> impl Strategy<Value = Option<Command>> {
    prop_oneof![
        Just(None),
        Just(Some(Command::Stop)),
        any::<f32>().prop_map(|r| Some(Command::Start(r))),
        any::<f32>().prop_map(|r| Some(Command::Speed(r))),
    ]
}

/// `a == b`, NaNs equal by their bits (a float survives the wire bit for bit).
fn same_bits(a: &Sense, b: &Sense) -> bool {
    let bits = |c: &Option<Command>| match c {
        Some(Command::Start(r)) => Some((0, r.to_bits())),
        Some(Command::Speed(r)) => Some((1, r.to_bits())),
        Some(Command::Stop) => Some((2, 0)),
        None => None,
    };
    a.seq == b.seq && a.counts == b.counts && bits(&a.command) == bits(&b.command)
}

proptest! {
    #[test]
    fn what_is_sent_is_read(
        seq in any::<u32>(),
        counts in prop::collection::vec(any::<i32>(), 0..=MAX_JOINTS),
        command in command(),
        torque in prop::collection::vec(any::<f32>(), 0..=MAX_JOINTS),
    ) {
        let s = sense(seq, &counts, command);
        let bytes = frame(&s);
        // One 0, at the end; within MAX_FRAME.
        prop_assert!(bytes.len() <= MAX_FRAME);
        prop_assert_eq!(bytes.iter().position(|b| *b == 0), Some(bytes.len() - 1));
        let got = read_all::<Sense>(&bytes);
        prop_assert_eq!(got.len(), 1);
        prop_assert!(same_bits(got[0].as_ref().unwrap(), &s));
        let a = Actuate {
            seq,
            torque: torque.iter().copied().collect(),
            state: DriveState::Fault(3),
            errors: seq / 2,
        };
        let got = read_all::<Actuate>(&frame(&a));
        let back = got[0].as_ref().unwrap();
        prop_assert_eq!(back.seq, a.seq);
        prop_assert_eq!(back.state, a.state);
        prop_assert_eq!(back.errors, a.errors);
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        prop_assert_eq!(bits(&back.torque), bits(&a.torque));
    }

    #[test]
    fn after_any_garbage_the_next_frame_is_read(
        garbage in prop::collection::vec(any::<u8>(), 0..300),
        seq in any::<u32>(),
    ) {
        let s = sense(seq, &[1, -2], Some(Command::Speed(2.0)));
        let mut bytes = garbage;
        bytes.push(0);
        bytes.extend(frame(&s));
        let got = read_all::<Sense>(&bytes);
        prop_assert_eq!(got.last().unwrap(), &Ok(s));
    }
}

/// Every single-bit error in a frame (its terminating 0 aside) is caught, and the clean frame
/// after it is read; for each of a few frames, all of its bits.
#[test]
fn no_single_bit_error_is_read_as_a_message() {
    let frames = [
        sense(0, &[0, 0], None),
        sense(7, &[131_072, -65_536], Some(Command::Start(1.0))),
        sense(
            u32::MAX,
            &[i32::MIN, i32::MAX, 5, -5, 0, 1],
            Some(Command::Stop),
        ),
    ];
    let next = sense(12, &[3, 4], None);
    let mut caught = [0usize; 5];
    for s in &frames {
        let clean = frame(s);
        for byte in 0..clean.len() - 1 {
            for bit in 0..8 {
                let mut bytes = clean.clone();
                bytes[byte] ^= 1 << bit;
                bytes.extend(frame(&next));
                let got = read_all::<Sense>(&bytes);
                let (last, rest) = got.split_last().unwrap();
                assert_eq!(
                    last,
                    &Ok(next.clone()),
                    "frame {s:?}, byte {byte}, bit {bit}"
                );
                for r in rest {
                    let e = r.as_ref().expect_err("a corrupted frame read as a message");
                    caught[*e as usize] += 1;
                }
            }
        }
    }
    // Most are caught by the CRC; a flip in a stuffing code, or into a 0, by the stuffing.
    assert!(
        caught[LinkError::Crc as usize] > 0 && caught[LinkError::Stuffing as usize] > 0,
        "{caught:?}"
    );
}

#[test]
fn a_frame_too_long_or_empty_is_an_error_and_the_next_is_read() {
    let s = sense(1, &[1, 2], None);
    let mut bytes = vec![0x55u8; 3 * MAX_FRAME];
    bytes.push(0);
    bytes.push(0); // an empty frame
    bytes.extend(frame(&s));
    let got = read_all::<Sense>(&bytes);
    assert_eq!(got, [Err(LinkError::TooLong), Err(LinkError::Empty), Ok(s)]);
}

#[test]
fn a_frame_is_at_most_max_frame_bytes_with_its_zero() {
    // MAX_FRAME − 1 bytes and the 0 are read as a frame (here not a stuffed one); one more
    // byte is too long.
    let mut at_most = vec![0x55u8; MAX_FRAME - 1];
    at_most.push(0);
    assert_eq!(read_all::<Sense>(&at_most), [Err(LinkError::Stuffing)]);
    let mut over = vec![0x55u8; MAX_FRAME];
    over.push(0);
    assert_eq!(read_all::<Sense>(&over), [Err(LinkError::TooLong)]);
}

#[test]
fn a_message_too_long_for_a_frame_is_refused() {
    // MAX_JOINTS joints at their longest fit a frame; a buffer too short for one is refused.
    let full = sense(
        u32::MAX,
        &[i32::MIN; MAX_JOINTS],
        Some(Command::Start(f32::NAN)),
    );
    assert!(frame(&full).len() <= MAX_FRAME);
    let mut small = [0u8; 8];
    assert_eq!(encode(&full, &mut small), Err(LinkError::TooLong));
}

proptest! {
    /// `frame` is the link's framing of any body: a message's postcard bytes frame as
    /// `encode` frames the message, and any body of up to the message's size reads back past
    /// the CRC (as that message, or as `Message` when it is not one).
    #[test]
    fn any_body_frames_as_the_link_frames_a_message(
        seq in any::<u32>(),
        counts in prop::collection::vec(any::<i32>(), 0..=MAX_JOINTS),
        command in command(),
        noise in prop::collection::vec(any::<u8>(), 0..60),
    ) {
        let s = sense(seq, &counts, command);
        let mut buf = [0u8; MAX_FRAME];
        let body = postcard::to_slice(&s, &mut buf).unwrap().to_vec();
        let mut out = vec![0u8; frame_len(body.len())];
        let n = pvfc_link::frame(&body, &mut out).unwrap();
        prop_assert_eq!(&out[..n], &frame(&s)[..]);
        // Both are the wire format, built here from its parts: COBS(body ‖ CRC) ‖ 0.
        const CRC: crc::Crc<u16> = crc::Crc::<u16>::new(&crc::CRC_16_IBM_SDLC);
        let mut raw = body.clone();
        raw.extend_from_slice(&CRC.checksum(&body).to_le_bytes());
        let mut wire = vec![0u8; cobs::max_encoding_length(raw.len())];
        let m = cobs::encode(&raw, &mut wire);
        wire.truncate(m);
        wire.push(0);
        prop_assert_eq!(&out[..n], &wire[..]);
        let mut out = vec![0u8; frame_len(noise.len())];
        let n = pvfc_link::frame(&noise, &mut out).unwrap();
        prop_assert_eq!(n, out.len(), "frame_len is the frame's length");
        let read = read_all::<Sense>(&out[..n]);
        prop_assert_eq!(read.len(), 1);
        prop_assert!(!matches!(read[0], Err(LinkError::Crc | LinkError::Stuffing)));
        // Too small a buffer is refused, not overrun.
        prop_assert_eq!(pvfc_link::frame(&noise, &mut out[..n - 1]), Err(LinkError::TooLong));
    }
}
