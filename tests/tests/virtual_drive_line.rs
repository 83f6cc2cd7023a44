//! The virtual drive on its line: injected faults become a master's typed errors (or are
//! read through), an echoing line returns every request, and the serve loop answers a
//! master over a pseudo-terminal with the line's timing.

use vfd_drives::{fc51, yd1000};
use vfd_runtime::prelude::*;
use vfd_runtime::virtual_drive::{Fault, Simulator};
use vfd_runtime::Request;
use vfd_tests::drive_protocols::YD1000_PROTOCOLS;
use vfd_tests::outcomes::timed_out;

mod faults {
    use super::*;
    use yd1000::registers::MaximumFrequency;

    #[test]
    fn injected_faults_become_typed_errors_and_tolerated_ones_do_not() {
        for protocol in YD1000_PROTOCOLS {
            let sim = Simulator::new(&yd1000::DRIVE);
            let mut master = sim.master(protocol);
            sim.inject(Fault::DropReply);
            timed_out(master.read::<MaximumFrequency>());
            sim.inject(Fault::Delay);
            timed_out(master.read::<MaximumFrequency>());
            sim.inject(Fault::CorruptChecksum);
            assert!(master.read::<MaximumFrequency>().is_err());
            sim.inject(Fault::WrongStation);
            assert!(master.read::<MaximumFrequency>().is_err());
            // Noise before the start byte, a split reply and an echo are read through.
            sim.inject(Fault::GarbageBefore(vec![0x00, 0xFF, 0x55]));
            assert_eq!(master.read::<MaximumFrequency>().unwrap(), Hertz(80.0));
            sim.inject(Fault::SplitBytes(2));
            assert_eq!(master.read::<MaximumFrequency>().unwrap(), Hertz(80.0));
            sim.inject(Fault::Noise);
            assert!(master.read::<MaximumFrequency>().is_err());
            sim.lock().clear_faults();
            assert_eq!(master.read::<MaximumFrequency>().unwrap(), Hertz(80.0));
            let mut other = sim.master(protocol).with_address(Some(9));
            sim.inject(Fault::AnswerBroadcast);
            assert_eq!(other.read::<MaximumFrequency>().unwrap(), Hertz(80.0));
        }
    }

    #[test]
    fn an_echoing_line_returns_every_request_until_cleared_even_when_the_drive_is_silent() {
        let protocol = yd1000::protocols::BINARY.protocol();
        let sim = Simulator::new(&yd1000::DRIVE);
        let mut frame = [0u8; 32];
        let request = Request::read::<MaximumFrequency>();
        let len = protocol
            .encode_request(&request, Some(1), &mut frame)
            .unwrap();
        let request = frame[..len].to_vec();
        let sent = |sim: &Simulator| -> Vec<Vec<u8>> {
            let mut input = request.clone();
            let sent = sim.lock().receive(protocol, &mut input);
            sent.into_iter().map(|t| t.bytes).collect()
        };
        let reply = sent(&sim).remove(0);
        sim.inject(Fault::EchoRequest);
        assert_eq!(sent(&sim), [request.clone(), reply.clone()]);
        assert_eq!(
            sent(&sim),
            [request.clone(), reply.clone()],
            "still echoing"
        );
        sim.inject(Fault::DropReply);
        assert_eq!(
            sent(&sim),
            std::slice::from_ref(&request),
            "the line echoes a silent drive's request"
        );
        sim.clear_faults();
        assert_eq!(sent(&sim), [reply]);
        assert_eq!(sim.requests(), 5);
    }
}

mod over_a_pseudo_terminal {
    use super::*;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    use vfd_runtime::transport::PseudoTerminal;
    use vfd_runtime::virtual_drive::serve;

    #[test]
    fn the_serve_loop_answers_a_master_with_the_lines_timing() {
        let (line, mut drive_end) = PseudoTerminal::open().unwrap().into_transports().unwrap();
        let sim = Simulator::new(&fc51::DRIVE);
        let stop = Arc::new(AtomicBool::new(false));
        let server = {
            let (sim, stop) = (sim.clone(), Arc::clone(&stop));
            std::thread::spawn(move || {
                serve(
                    &sim,
                    fc51::protocols::MODBUS.protocol(),
                    &mut drive_end,
                    fc51::SERIAL.default,
                    &stop,
                )
            })
        };
        let mut master = Master::new(
            line,
            &fc51::protocols::MODBUS,
            fc51::SERIAL.default,
            fc51::SERIAL.timing,
        )
        .with_address(Some(1));
        master
            .write_persistent::<fc51::registers::MaximumReference>(50.0)
            .unwrap();
        assert_eq!(
            master.read::<fc51::registers::MaximumReference>().unwrap(),
            50.0
        );
        sim.inject(Fault::SplitBytes(1));
        assert_eq!(
            master.read::<fc51::registers::MaximumReference>().unwrap(),
            50.0
        );
        let mut other = Master::new(
            master.into_transport(),
            &fc51::protocols::MODBUS,
            fc51::SERIAL.default,
            fc51::SERIAL.timing,
        )
        .with_address(Some(2));
        timed_out(other.read::<fc51::registers::MaximumReference>());
        stop.store(true, Ordering::Relaxed);
        server.join().unwrap().unwrap();
        drop(other);
    }
}
