//! Any bytes through the hardware-in-the-loop link's decoders (`pvfc-link`), as the drive's
//! and the host's receivers get them: a message or a typed error at every frame's 0, never a
//! panic; and every message read is written again and read back as the same frame.
//!
//! The first byte chooses how the rest is sent: even, as a raw byte stream (noise, cut and
//! joined frames); odd, as a message body framed correctly (CRC and stuffing added), so that
//! the message decoder itself meets arbitrary bodies behind a valid CRC.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pvfc_link::{encode, frame, frame_len, Actuate, Decoder, LinkError, Sense, MAX_FRAME};
use serde::{de::DeserializeOwned, Serialize};

/// Feeds `bytes` to a decoder of `M`; each message read must encode again, and its frame must
/// decode to a message that encodes to the same frame.
fn check<M: Serialize + DeserializeOwned>(bytes: &[u8]) {
    let mut decoder = Decoder::<M>::new();
    for &b in bytes {
        match decoder.push(b) {
            None | Some(Err(_)) => {}
            Some(Ok(message)) => {
                let mut frame = [0u8; MAX_FRAME];
                let n = encode(&message, &mut frame).expect("a message read fits a frame");
                assert_eq!(frame[n - 1], 0, "a frame ends with its 0");
                assert!(!frame[..n - 1].contains(&0), "no 0 inside a frame");
                let mut again = Decoder::<M>::new();
                let read = frame[..n - 1]
                    .iter()
                    .map(|&b| again.push(b))
                    .all(|r| r.is_none());
                assert!(read, "a frame's bytes before its 0 give nothing");
                let back = again
                    .push(0)
                    .expect("a frame ends at its 0")
                    .expect("it reads back");
                let mut frame2 = [0u8; MAX_FRAME];
                let n2 = encode(&back, &mut frame2).expect("it encodes again");
                assert_eq!(&frame[..n], &frame2[..n2], "read back as the same frame");
            }
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    if mode % 2 == 0 {
        check::<Sense>(rest);
        check::<Actuate>(rest);
        return;
    }
    // The body framed as the link frames it, its 0 included.
    let mut stuffed = vec![0u8; frame_len(rest.len())];
    let n = frame(rest, &mut stuffed).expect("frame_len bytes hold the frame");
    stuffed.truncate(n);
    check::<Sense>(&stuffed);
    check::<Actuate>(&stuffed);
    // A frame longer than the link's reads as too long, never as a message.
    if stuffed.len() > MAX_FRAME {
        let mut decoder = Decoder::<Sense>::new();
        let last = stuffed.iter().filter_map(|&b| decoder.push(b)).last();
        assert_eq!(last.map(|r| r.err()), Some(Some(LinkError::TooLong)));
    }
});
