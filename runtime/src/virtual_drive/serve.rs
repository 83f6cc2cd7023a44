//! Serving a virtual drive over any [`Transport`] (a pseudo-terminal, a serial port) in
//! wall time, with the line's timing: a reply starts after the request's last byte and the
//! protocol's frame gap, unfinished frames are dropped after the gap or the drive's frame
//! abandon time, and the simulated clock follows the wall clock.

use super::{Fault, Simulator};
use crate::protocol::Protocol;
use crate::serial::SerialSettings;
use crate::transport::Transport;
use std::io;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How long one wait for bytes lasts; the stop flag is looked at this often.
const POLL: Duration = Duration::from_millis(5);

/// Bytes sent while the line is jammed by [`Fault::Noise`].
const NOISE: [u8; 4] = [0x00, 0xFF, 0x55, 0xAA];

/// Answers requests in `protocol` arriving on `transport` until `stop` is set, at the line
/// `settings` (which give the character time the timing derives from). Returns transport
/// errors; never panics.
pub fn serve<T: Transport>(
    simulator: &Simulator,
    protocol: &'static Protocol,
    transport: &mut T,
    settings: SerialSettings,
    stop: &AtomicBool,
) -> io::Result<()> {
    let timing = simulator.lock().drive().serial.timing;
    let char_time = settings.char_time();
    let gap = char_time
        .mul_f32(protocol.frame_gap_chars)
        .max(protocol.timing.frame_gap_min);
    // A silence this long inside a frame drops it (where the drive states such a limit).
    let inner_gap = char_time.mul_f32(protocol.timing.max_inner_gap_chars);
    // After this much silence a frame that another variant of the protocol could still
    // have continued (a CR that an LF may follow) is taken as it stands.
    let settle = char_time * 2;
    let mut input = Vec::new();
    let mut buf = [0u8; 256];
    let mut clock = Instant::now();
    let mut last_byte = clock;
    while !stop.load(Ordering::Relaxed) {
        let got = transport.receive(&mut buf, Instant::now() + POLL)?;
        let now = Instant::now();
        simulator.advance(now - clock);
        clock = now;
        let mut transmissions = Vec::new();
        if got > 0 {
            input.extend_from_slice(&buf[..got]);
            last_byte = now;
        } else {
            let quiet = now - last_byte;
            if quiet >= settle {
                transmissions = simulator
                    .lock()
                    .receive_before_silence(protocol, &mut input);
            }
            let dropped_by_gap = !gap.is_zero() && quiet >= gap;
            let dropped_inside = !inner_gap.is_zero() && quiet >= inner_gap;
            let abandoned = !timing.frame_abandon.is_zero() && quiet >= timing.frame_abandon;
            if dropped_by_gap || dropped_inside || abandoned {
                input.clear();
                simulator.lock().line_silent();
            }
        }
        if simulator.has_fault(&Fault::Noise) {
            transport.send(&NOISE)?;
        }
        transmissions.extend(simulator.lock().receive(protocol, &mut input));
        for transmission in transmissions {
            // The reply starts after the request's last byte and the frame gap, and the
            // wait the drive's reply-delay registers set.
            std::thread::sleep(gap.max(char_time) + transmission.wait);
            if transmission.delayed {
                let timeout = timing.reply_timeout(
                    &settings,
                    transmission.request_len,
                    usize::from(protocol.max_frame_len),
                );
                // Past the master's deadline (which adds the host latency), within the
                // window in which it still drops a late reply.
                std::thread::sleep(
                    timeout + crate::serial::HOST_LATENCY + Duration::from_millis(20),
                );
            }
            match transmission.split {
                Some(chars) => {
                    for byte in &transmission.bytes {
                        transport.send(std::slice::from_ref(byte))?;
                        std::thread::sleep(char_time * chars.max(1));
                    }
                }
                None => transport.send(&transmission.bytes)?,
            }
        }
    }
    Ok(())
}
