//! Serving a virtual drive over any [`Transport`] (a pseudo-terminal, a serial port, an
//! accepted TCP connection) in wall time, with the line's timing: a reply starts after the request's last byte and the
//! protocol's frame gap (none where the protocol states none) plus the drive's reply delay,
//! unfinished frames are dropped after the gap or the drive's frame abandon time, and the
//! simulated clock follows the wall clock. The loop waits for bytes only until the next of
//! these moments, so a silence is noticed when it is due, not at the next idle poll.
//! Several drives can share the transport as stations of one multi-drop bus
//! ([`serve_bus`]); one drive is the one-station case ([`serve`]).

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

/// One station of a multi-drop bus served by [`serve_bus`]: a virtual drive (its station
/// number set with [`super::VirtualDrive::set_address`]) and the protocol it speaks.
#[derive(Debug, Clone)]
pub struct BusStation {
    /// The virtual drive.
    pub simulator: Simulator,
    /// The protocol it reads frames in (stations of one bus share its framing: see
    /// [`same_framing`]).
    pub protocol: &'static Protocol,
}

/// Whether two protocols frame requests alike, so that drives speaking them can share a
/// line: both are entries of the same protocol file (their names are that file's). Two
/// drives' Modbus RTU entries share a framing; Modbus RTU and Toshiba binary do not.
pub fn same_framing(a: &Protocol, b: &Protocol) -> bool {
    a.name == b.name
}

/// Answers requests in `protocol` arriving on `transport` until `stop` is set, at the line
/// `settings` (which give the character time the timing derives from). Returns transport
/// errors; never panics. The one-station case of [`serve_bus`].
pub fn serve<T: Transport>(
    simulator: &Simulator,
    protocol: &'static Protocol,
    transport: &mut T,
    settings: SerialSettings,
    stop: &AtomicBool,
) -> io::Result<()> {
    let station = BusStation {
        simulator: simulator.clone(),
        protocol,
    };
    serve_bus(std::slice::from_ref(&station), transport, settings, stop)
}

/// What the bus loop keeps for one station: its input (every station hears every byte,
/// and reads them with its own protocol) and its timing.
struct Listening<'a> {
    station: &'a BusStation,
    input: Vec<u8>,
    /// The protocol's frame gap at the line's speed.
    gap: Duration,
    /// A silence this long inside a frame drops it (where the drive states such a limit).
    inner_gap: Duration,
    /// The drive's frame abandon time.
    abandon: Duration,
    /// The drive's timing (for a delayed reply).
    timing: crate::serial::DriveTiming,
}

/// Serves a multi-drop bus: every station in `stations` hears every byte on `transport`
/// and answers only the requests for its own station number, as drives on one RS-485
/// line do (a broadcast is carried out by every station it reaches and answered by the
/// one its protocol's rule names, if any). The timing is [`serve`]'s: a reply starts after
/// the request's last byte, the protocol's frame gap and the drive's reply delay;
/// unfinished frames are dropped after the gap or the drive's frame abandon time; the
/// simulated clocks follow the wall clock. Stations can be unplugged while the bus runs
/// ([`Simulator::set_unplugged`]). Runs until `stop` is set; returns transport errors;
/// never panics.
pub fn serve_bus<T: Transport>(
    stations: &[BusStation],
    transport: &mut T,
    settings: SerialSettings,
    stop: &AtomicBool,
) -> io::Result<()> {
    let char_time = settings.char_time();
    let mut listening: Vec<Listening<'_>> = stations
        .iter()
        .map(|station| {
            let timing = station.simulator.lock().drive().serial.timing;
            let protocol = station.protocol;
            Listening {
                station,
                input: Vec::new(),
                gap: char_time
                    .mul_f32(protocol.frame_gap_chars)
                    .max(protocol.timing.frame_gap_min),
                inner_gap: char_time.mul_f32(protocol.timing.max_inner_gap_chars),
                abandon: timing.frame_abandon,
                timing,
            }
        })
        .collect();
    // After this much silence a frame that another variant of the protocol could still
    // have continued (a CR that an LF may follow) is taken as it stands.
    let settle = char_time * 2;
    let mut buf = [0u8; 256];
    let mut clock = Instant::now();
    let mut last_byte = clock;
    while !stop.load(Ordering::Relaxed) {
        let pending = listening.iter().any(|l| !l.input.is_empty());
        let mut silences = vec![settle];
        for l in &listening {
            silences.extend([l.gap, l.inner_gap, l.abandon]);
        }
        let deadline = next_wait(clock, pending.then_some(last_byte), &silences);
        let got = transport.receive(&mut buf, deadline)?;
        let now = Instant::now();
        for l in &listening {
            l.station.simulator.advance(now - clock);
        }
        clock = now;
        // (station, transmission) in the order the stations made them.
        let mut transmissions = Vec::new();
        if got > 0 {
            for l in &mut listening {
                l.input.extend_from_slice(&buf[..got]);
            }
            last_byte = now;
        } else {
            let quiet = now - last_byte;
            for (index, l) in listening.iter_mut().enumerate() {
                let dropped = [l.gap, l.inner_gap, l.abandon]
                    .iter()
                    .any(|limit| !limit.is_zero() && quiet >= *limit);
                // The bytes before a silence are read as a whole first (a frame that only
                // the silence ends: a request of a function the drive lacks), even when
                // the silence is one that drops an unfinished frame.
                if !l.input.is_empty() && (quiet >= settle || dropped) {
                    let sent = l
                        .station
                        .simulator
                        .lock()
                        .receive_before_silence(l.station.protocol, &mut l.input);
                    transmissions.extend(sent.into_iter().map(|t| (index, t)));
                }
                if dropped && !l.input.is_empty() {
                    l.input.clear();
                }
                if dropped {
                    l.station.simulator.lock().line_silent();
                }
            }
        }
        for l in &listening {
            if l.station.simulator.has_fault(&Fault::Noise) {
                transport.send(&NOISE)?;
            }
        }
        for (index, l) in listening.iter_mut().enumerate() {
            let sent = l
                .station
                .simulator
                .lock()
                .receive(l.station.protocol, &mut l.input);
            transmissions.extend(sent.into_iter().map(|t| (index, t)));
        }
        // The line is free from the request's last byte on; each transmission keeps the
        // frame gap after whatever went before it.
        let mut line_free = last_byte;
        for (index, transmission) in transmissions {
            let l = &listening[index];
            let protocol = l.station.protocol;
            // The reply starts after the request's last byte and the frame gap, and the
            // wait the drive's reply-delay registers set.
            sleep_until(line_free + l.gap + transmission.wait);
            if transmission.delayed {
                let timeout = l.timing.reply_timeout(
                    &settings,
                    transmission.request_len,
                    usize::from(protocol.max_frame_len),
                );
                // Past the master's deadline (which adds the host latency and what the
                // transport adds: a network), within the window in which it still drops a
                // late reply. The margin grows with what the transport allows for: a
                // master that uncertain of delivery may also be scheduled that late.
                std::thread::sleep(
                    timeout
                        + crate::serial::HOST_LATENCY
                        + transport.allowance()
                        + Duration::from_millis(20)
                        + transport.allowance() / 4,
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
