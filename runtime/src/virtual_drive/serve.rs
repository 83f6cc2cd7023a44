//! Serving a virtual drive over any [`Transport`] (a pseudo-terminal, a serial port, an
//! accepted TCP connection) in wall time, with the line's timing: a reply starts after the request's last byte and the
//! protocol's frame gap (none where the protocol states none) plus the drive's reply delay,
//! unfinished frames are dropped after the gap or the drive's frame abandon time, and the
//! simulated clock follows the wall clock. The loop waits for bytes only until the next of
//! these moments, so a silence is noticed when it is due, not at the next idle poll.

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
        let deadline = next_wait(
            clock,
            (!input.is_empty()).then_some(last_byte),
            &[settle, gap, inner_gap, timing.frame_abandon],
        );
        let got = transport.receive(&mut buf, deadline)?;
        let now = Instant::now();
        simulator.advance(now - clock);
        clock = now;
        let mut transmissions = Vec::new();
        if got > 0 {
            input.extend_from_slice(&buf[..got]);
            last_byte = now;
        } else {
            let quiet = now - last_byte;
            let dropped_by_gap = !gap.is_zero() && quiet >= gap;
            let dropped_inside = !inner_gap.is_zero() && quiet >= inner_gap;
            let abandoned = !timing.frame_abandon.is_zero() && quiet >= timing.frame_abandon;
            let dropped = dropped_by_gap || dropped_inside || abandoned;
            // The bytes before a silence are read as a whole first (a frame that only the
            // silence ends: a request of a function the drive lacks), even when the
            // silence is one that drops an unfinished frame.
            if quiet >= settle || dropped {
                transmissions = simulator
                    .lock()
                    .receive_before_silence(protocol, &mut input);
            }
            if dropped {
                input.clear();
                simulator.lock().line_silent();
            }
        }
        if simulator.has_fault(&Fault::Noise) {
            transport.send(&NOISE)?;
        }
        transmissions.extend(simulator.lock().receive(protocol, &mut input));
        // The line is free from the request's last byte on; each transmission keeps the
        // frame gap after whatever went before it.
        let mut line_free = last_byte;
        for transmission in transmissions {
            // The reply starts after the request's last byte and the frame gap, and the
            // wait the drive's reply-delay registers set.
            sleep_until(line_free + gap + transmission.wait);
            if transmission.delayed {
                let timeout = timing.reply_timeout(
                    &settings,
                    transmission.request_len,
                    usize::from(protocol.max_frame_len),
                );
                // Past the master's deadline (which adds the host latency and what the
                // transport adds: a network), within the window in which it still drops a
                // late reply.
                std::thread::sleep(
                    timeout
                        + crate::serial::HOST_LATENCY
                        + transport.allowance()
                        + Duration::from_millis(20),
                );
            }
            match transmission.split {
                Some(chars) => {
                    for byte in &transmission.bytes {
                        transport.send(std::slice::from_ref(byte))?;
                        std::thread::sleep(char_time * chars.max(1));
                    }
                    line_free = Instant::now();
                }
                None => {
                    transport.send(&transmission.bytes)?;
                    line_free = Instant::now() + settings.wire_time(transmission.bytes.len());
                }
            }
        }
    }
    Ok(())
}

/// Sleeps until `due` (at once if it has passed).
fn sleep_until(due: Instant) {
    let now = Instant::now();
    if due > now {
        std::thread::sleep(due - now);
    }
}

/// Until when the loop waits for bytes at `now`: the first of the silences in `silences`
/// (after the last byte of unfinished input, when there is some) still to come, and at most
/// [`POLL`] (when the stop flag and the noise fault are looked at).
fn next_wait(now: Instant, last_byte: Option<Instant>, silences: &[Duration]) -> Instant {
    let idle = now + POLL;
    let Some(last_byte) = last_byte else {
        return idle;
    };
    silences
        .iter()
        .filter(|silence| !silence.is_zero())
        .map(|silence| last_byte + *silence)
        .filter(|due| *due > now)
        .fold(idle, Instant::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_input_the_loop_waits_the_idle_poll() {
        let now = Instant::now();
        let ms = Duration::from_millis;
        assert_eq!(next_wait(now, None, &[ms(1), ms(2)]), now + POLL);
    }

    #[test]
    fn with_input_the_loop_wakes_at_the_next_silence_due() {
        let now = Instant::now();
        let us = Duration::from_micros;
        let last = now - us(100);
        // 0.2 ms settle, no gap, 1.5 ms inner gap: the settle comes first.
        assert_eq!(
            next_wait(now, Some(last), &[us(200), Duration::ZERO, us(1500)]),
            last + us(200)
        );
        // Once the settle has passed, the inner gap is next.
        let later = last + us(300);
        assert_eq!(
            next_wait(later, Some(last), &[us(200), Duration::ZERO, us(1500)]),
            last + us(1500)
        );
        // Every silence passed (or longer than the idle poll): the idle poll.
        let much_later = last + Duration::from_secs(2);
        assert_eq!(
            next_wait(much_later, Some(last), &[us(200), us(1500)]),
            much_later + POLL
        );
        assert_eq!(
            next_wait(now, Some(last), &[Duration::from_secs(1)]),
            now + POLL
        );
    }
}
