//! The threads that read a child's two streams while a call runs: its
//! frames (the launcher's report, each call's start and result, decoded as
//! they are whole, a result too large refused unread) and what the
//! student's code printed (cut per call at the child's mark, capped), each
//! told to the loop waiting on the call as an [`Event`].

use std::io::Read;
use std::process::ExitStatus;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{mpsc, Arc};
use std::thread;

use crate::isolate::protections::Protections;
use crate::isolate::wire::{self, Frame};

/// The most of the student's output kept for the report, per call.
pub(super) const OUTPUT_CAP: usize = 8 * 1024;

/// What the threads watching a child tell the loop waiting on a call.
pub(super) enum Event {
    /// The launcher's report of the protections in force.
    Sandbox(Protections),
    /// The child program waits for its first request.
    Ready,
    /// A call started: its clock starts.
    Started,
    /// A call's whole result frame.
    Result(Vec<u8>),
    /// The launcher could not start the child program (with the nonce it
    /// was given, if the frame is its own).
    LaunchFailed {
        nonce: [u8; wire::NONCE_LEN],
        why: String,
    },
    /// A result frame announced this many bytes, more than allowed.
    TooLarge(usize),
    /// The channel held something that is not a frame.
    Garbled(String),
    /// The frames' pipe closed.
    StreamEnd,
    Exited(ExitStatus),
}

/// Reads the frames as they come, telling the waiting loop of each as it
/// is whole: the launcher's report, each call's start, CPU time and
/// result. A result announced larger than `cap` is refused unread; a
/// stream that holds something other than frames is said once, and the
/// rest drained so the child never blocks on a full pipe.
pub(super) fn watch_frames(
    mut stream: impl Read + Send + 'static,
    cap: Arc<AtomicUsize>,
    tx: mpsc::Sender<Event>,
) {
    thread::spawn(move || {
        let mut bytes: Vec<u8> = Vec::new();
        let mut buf = vec![0u8; 64 * 1024];
        let mut broken = false;
        while let Ok(n) = stream.read(&mut buf) {
            if n == 0 {
                break;
            }
            if broken {
                continue;
            }
            bytes.extend_from_slice(&buf[..n]);
            loop {
                match wire::frame_at(&bytes) {
                    Ok(wire::Pending::Whole(len)) => {
                        let frame: Vec<u8> = bytes.drain(..len).collect();
                        let event = match frame[0] {
                            wire::SANDBOX_TAG => match wire::decode_frames(&frame) {
                                Ok(mut f) => match f.pop() {
                                    Some(Frame::Sandbox(s)) => Event::Sandbox(s),
                                    _ => Event::Garbled("no launcher report".into()),
                                },
                                Err(e) => Event::Garbled(e.to_string()),
                            },
                            wire::STARTED_TAG => Event::Started,
                            wire::READY_TAG => Event::Ready,
                            wire::RESULT_TAG => {
                                if len > cap.load(Ordering::Relaxed) {
                                    Event::TooLarge(len)
                                } else {
                                    Event::Result(frame)
                                }
                            }
                            _ => match wire::decode_frames(&frame) {
                                Ok(mut f) => match f.pop() {
                                    Some(Frame::LaunchFailed { nonce, why }) => {
                                        Event::LaunchFailed { nonce, why }
                                    }
                                    _ => Event::Garbled("an unexpected frame".into()),
                                },
                                Err(e) => Event::Garbled(e.to_string()),
                            },
                        };
                        broken = matches!(event, Event::Garbled(_) | Event::TooLarge(_));
                        let _ = tx.send(event);
                        if broken {
                            bytes = Vec::new();
                            break;
                        }
                    }
                    Ok(wire::Pending::Partial(Some(total)))
                        if total > cap.load(Ordering::Relaxed) =>
                    {
                        // Refused before it is read: no memory for it.
                        let _ = tx.send(Event::TooLarge(total));
                        broken = true;
                        bytes = Vec::new();
                        break;
                    }
                    Ok(wire::Pending::Partial(_)) => break,
                    Err(e) => {
                        let _ = tx.send(Event::Garbled(e.to_string()));
                        broken = true;
                        bytes = Vec::new();
                        break;
                    }
                }
            }
        }
        let _ = tx.send(Event::StreamEnd);
    });
}

/// Reads what the student's code printed, cut into one text per call at
/// each [`wire::CALL_END`] (each cut at 8 KiB); at the end of the stream,
/// what the last call printed before the child died or exited.
pub(super) fn drain(mut stream: impl Read + Send + 'static) -> mpsc::Receiver<String> {
    let (tx, rx) = mpsc::channel();
    thread::spawn(move || {
        let mark = wire::CALL_END;
        let mut kept = Vec::new();
        let mut cut = false;
        // How much of the mark the latest bytes matched.
        let mut matched = 0;
        let mut buf = vec![0u8; 64 * 1024];
        let finish = |kept: &mut Vec<u8>, cut: &mut bool| {
            let mut s = String::from_utf8_lossy(kept).into_owned();
            if *cut {
                s.push_str("\n[... output cut ...]\n");
            }
            kept.clear();
            *cut = false;
            s
        };
        let keep = |kept: &mut Vec<u8>, cut: &mut bool, bytes: &[u8]| {
            let room = OUTPUT_CAP.saturating_sub(kept.len());
            kept.extend_from_slice(&bytes[..bytes.len().min(room)]);
            *cut |= bytes.len() > room;
        };
        // Keep reading past the cap so the child never blocks on a full pipe.
        while let Ok(n) = stream.read(&mut buf) {
            if n == 0 {
                break;
            }
            let chunk = &buf[..n];
            let mut i = 0;
            while i < n {
                if matched == 0 {
                    // Up to the next byte that can start the mark, found
                    // by the C library (a flood must cost no time, even
                    // in a debug build).
                    let rest = &chunk[i..];
                    let at = first_nul(rest).unwrap_or(rest.len());
                    keep(&mut kept, &mut cut, &rest[..at]);
                    i += at;
                    if i == n {
                        break;
                    }
                }
                let b = chunk[i];
                i += 1;
                if b == mark[matched] {
                    matched += 1;
                    if matched == mark.len() {
                        matched = 0;
                        let _ = tx.send(finish(&mut kept, &mut cut));
                    }
                    continue;
                }
                // Not the mark after all: what it matched was output. The
                // mark's first byte occurs once in it, so a mismatch can
                // only restart the match at this byte.
                keep(&mut kept, &mut cut, &mark[..matched]);
                matched = usize::from(b == mark[0]);
                if matched == 0 {
                    keep(&mut kept, &mut cut, &[b]);
                }
            }
        }
        keep(&mut kept, &mut cut, &mark[..matched]);
        let _ = tx.send(finish(&mut kept, &mut cut));
    });
    rx
}

/// Where the first NUL byte (the mark's first) is.
pub(super) fn first_nul(bytes: &[u8]) -> Option<usize> {
    // SAFETY: memchr reads `bytes.len()` bytes from a valid slice.
    let p = unsafe { libc::memchr(bytes.as_ptr().cast(), 0, bytes.len()) };
    (!p.is_null()).then(|| p as usize - bytes.as_ptr() as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The output is cut at each call's mark, a mark cut across reads or
    /// begun and abandoned is output, and the last text comes at the end.
    #[test]
    fn output_is_cut_per_call_at_the_mark() {
        let mut stream = b"first\n".to_vec();
        stream.extend_from_slice(wire::CALL_END);
        // A mark's start that is not a mark, then the second call's mark.
        stream.extend_from_slice(b"\x00mesh\x00second");
        stream.extend_from_slice(wire::CALL_END);
        stream.extend_from_slice(b"dying words");
        let rx = drain(std::io::Cursor::new(stream));
        let got: Vec<String> = rx.iter().collect();
        assert_eq!(got, ["first\n", "\u{0}mesh\u{0}second", "dying words"]);
    }

    #[test]
    fn a_flood_is_cut_for_each_call() {
        let mut stream = vec![b'x'; 3 * OUTPUT_CAP];
        stream.extend_from_slice(wire::CALL_END);
        stream.extend_from_slice(b"short");
        let got: Vec<String> = drain(std::io::Cursor::new(stream)).iter().collect();
        assert_eq!(got.len(), 2);
        assert!(got[0].ends_with("[... output cut ...]\n") && got[0].len() < OUTPUT_CAP + 64);
        assert_eq!(got[1], "short");
    }
}
