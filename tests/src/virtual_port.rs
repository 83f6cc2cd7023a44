//! A virtual drive served on a pseudo-terminal in this process, for programs we did not
//! write (LinuxCNC components, mbpoll, minimalmodbus) that open its device as a serial port.

/// A virtual drive served on a pseudo-terminal whose slave path a LinuxCNC component opens
/// as its serial port; served until dropped.
pub struct VirtualPort {
    /// The device the component opens (`/dev/pts/N`).
    pub path: String,
    /// The virtual drive, to look at its state and inject faults while it is served.
    pub simulator: vfd_runtime::virtual_drive::Simulator,
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
    server: Option<std::thread::JoinHandle<std::io::Result<()>>>,
}

impl VirtualPort {
    /// Serves `drive` speaking `protocol` (an id of the drive's) at `address`, at the line
    /// `settings`.
    pub fn serve(
        drive: &'static vfd_runtime::DriveInfo,
        protocol: &str,
        address: u8,
        settings: vfd_runtime::serial::SerialSettings,
    ) -> VirtualPort {
        use vfd_runtime::transport::PseudoTerminal;
        use vfd_runtime::virtual_drive::{serve, Simulator};
        let protocol = drive
            .protocols
            .iter()
            .copied()
            .find(|p| p.id == protocol)
            .unwrap_or_else(|| panic!("{} speaks no protocol {protocol}", drive.id));
        let simulator = Simulator::new(drive);
        simulator.lock().set_address(address);
        let pty = PseudoTerminal::open().expect("a pseudo-terminal");
        let path = pty.slave_path().display().to_string();
        let mut ours = pty.master().expect("the master side");
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let server = {
            let (simulator, stop) = (simulator.clone(), stop.clone());
            std::thread::spawn(move || serve(&simulator, protocol, &mut ours, settings, &stop))
        };
        VirtualPort {
            path,
            simulator,
            stop,
            server: Some(server),
        }
    }
}

impl Drop for VirtualPort {
    fn drop(&mut self) {
        self.stop.store(true, std::sync::atomic::Ordering::SeqCst);
        if let Some(server) = self.server.take() {
            let _ = server.join();
        }
    }
}
