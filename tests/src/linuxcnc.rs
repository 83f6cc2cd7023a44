//! LinuxCNC's hand-written VFD components (Debian `linuxcnc-uspace`) as independent
//! masters: a HAL session under `halrun` that loads a component unmodified, and `halcmd`
//! to set its input pins and read its output pins, the way a LinuxCNC machine's HAL file
//! drives it.
//!
//! HAL keeps its pins in one shared-memory segment per machine, so one session runs at a
//! time on the machine: [`Hal::start`] holds a lock across the tests of a binary and a lock
//! directory in the temporary folder across processes (two test runs at once wait for each
//! other; a lock whose process is gone is taken over). Run as root, `rtapi_app` drops to the uid in `RTAPI_UID` and binds
//! its socket in `$HOME`: the session gets a `HOME` of its own that this uid can write.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// Whether `halrun` is installed (Debian's `linuxcnc-uspace`).
pub fn halrun_installed() -> bool {
    Command::new("halrun")
        .arg("-h")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok()
}

/// The uid `rtapi_app` runs as when started by root (`nobody`).
const UNPRIVILEGED_UID: &str = "65534";

static ONE_SESSION: Mutex<()> = Mutex::new(());

/// The machine-wide lock: a directory holding the pid of the process whose session runs.
struct MachineLock(PathBuf);

impl MachineLock {
    /// Waits (up to 10 minutes) until no other live process holds the lock, then takes it.
    fn take() -> MachineLock {
        let dir = std::env::temp_dir().join("vfd-linuxcnc-hal.lock");
        let end = Instant::now() + Duration::from_secs(600);
        loop {
            if std::fs::create_dir(&dir).is_ok() {
                let _ = std::fs::write(dir.join("pid"), std::process::id().to_string());
                return MachineLock(dir);
            }
            let holder = std::fs::read_to_string(dir.join("pid")).unwrap_or_default();
            let alive = holder
                .trim()
                .parse::<u32>()
                .is_ok_and(|pid| Path::new(&format!("/proc/{pid}")).exists());
            if !alive && !holder.is_empty() {
                // Its process is gone: take it over.
                let _ = std::fs::remove_dir_all(&dir);
                continue;
            }
            assert!(
                Instant::now() < end,
                "another HAL session (pid {holder}) held {} for 10 minutes",
                dir.display()
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }
}

impl Drop for MachineLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A running HAL session: `halrun` reading commands from a pipe, its output in a log.
pub struct Hal {
    child: Child,
    commands: ChildStdin,
    home: PathBuf,
    log: PathBuf,
    // Dropped after the session ends (fields drop in order, after `Drop::drop`).
    _machine: MachineLock,
    _one: MutexGuard<'static, ()>,
}

impl Hal {
    /// Starts a HAL session whose files (its `HOME`, its log) are in `dir`, after unloading
    /// whatever an earlier session left loaded.
    pub fn start(dir: &Path) -> Hal {
        let one = ONE_SESSION.lock().unwrap_or_else(|e| e.into_inner());
        let machine = MachineLock::take();
        let home = dir.join("hal-home");
        std::fs::create_dir_all(&home).expect("a HOME for the HAL session");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&home, std::fs::Permissions::from_mode(0o777))
                .expect("the HAL session's HOME is writable by its uid");
        }
        let log = dir.join("halrun.log");
        let mut unload = Command::new("halrun");
        unload.arg("-U");
        Self::environment(&mut unload, &home);
        let _ = unload.stdout(Stdio::null()).stderr(Stdio::null()).status();
        let mut command = Command::new("halrun");
        Self::environment(&mut command, &home);
        let mut child = command
            .current_dir(dir)
            .stdin(Stdio::piped())
            .stdout(std::fs::File::create(&log).expect("halrun log"))
            .stderr(std::fs::File::create(dir.join("halrun.err")).expect("halrun log"))
            .spawn()
            .expect("halrun starts");
        let commands = child.stdin.take().expect("piped");
        Hal {
            child,
            commands,
            home,
            log,
            _machine: machine,
            _one: one,
        }
    }

    fn environment(command: &mut Command, home: &Path) {
        command.env("HOME", home);
        // Components written in Python (mitsub_vfd) print to the log as they go, not when
        // a block buffer fills: a test waits on what they say (`wait_for_log`).
        command.env("PYTHONUNBUFFERED", "1");
        if running_as_root() {
            command.env("RTAPI_UID", UNPRIVILEGED_UID);
        }
    }

    /// Runs one halcmd line in the session (`loadusr -Wn spindle gs2_vfd ...`, `loadrt`,
    /// `net`): sent to `halrun`, which runs it in order with the others.
    pub fn run(&mut self, line: &str) {
        writeln!(self.commands, "{line}").expect("halrun takes commands");
        self.commands.flush().expect("flushed");
    }

    /// Runs `halcmd` with `args` against the session and returns its standard output;
    /// panics with its error when it fails.
    pub fn halcmd(&self, args: &[&str]) -> String {
        let mut command = Command::new("halcmd");
        Self::environment(&mut command, &self.home);
        let output = command.args(args).output().expect("halcmd runs");
        assert!(
            output.status.success(),
            "halcmd {args:?} failed: {}{}\nhalrun's log:\n{}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr),
            self.log_text()
        );
        String::from_utf8_lossy(&output.stdout).trim().to_owned()
    }

    /// Sets an input pin.
    pub fn setp(&self, pin: &str, value: impl std::fmt::Display) {
        self.halcmd(&["setp", pin, &value.to_string()]);
    }

    /// A pin's value as halcmd prints it (`TRUE`, `FALSE`, `1500`, `49.98`).
    pub fn getp(&self, pin: &str) -> String {
        self.halcmd(&["getp", pin])
    }

    /// A float or integer pin's value.
    pub fn number(&self, pin: &str) -> f64 {
        let text = self.getp(pin);
        text.parse()
            .unwrap_or_else(|_| panic!("pin {pin} reads {text:?}, not a number"))
    }

    /// A bit pin's value.
    pub fn bit(&self, pin: &str) -> bool {
        match self.getp(pin).as_str() {
            "TRUE" => true,
            "FALSE" => false,
            other => panic!("pin {pin} reads {other:?}, not a bit"),
        }
    }

    /// Whether a pin exists (for components whose pin set depends on their options).
    pub fn has_pin(&self, pin: &str) -> bool {
        let mut command = Command::new("halcmd");
        Self::environment(&mut command, &self.home);
        command
            .args(["getp", pin])
            .output()
            .is_ok_and(|o| o.status.success())
    }

    /// Waits up to `limit` until `pin` exists: a component loaded with `loadusr -Wn` is
    /// ready once its pins are (`run` returns before `halrun` has loaded it).
    pub fn wait_for_pin(&self, pin: &str, limit: Duration) {
        let end = Instant::now() + limit;
        while !self.has_pin(pin) {
            assert!(
                Instant::now() < end,
                "no pin {pin} after {limit:?}: the component did not start\nhalrun's log:\n{}",
                self.log_text()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// Waits up to `limit` until `pin`'s value satisfies `ready`; the value then, or a panic
    /// naming the last value and the session's log.
    pub fn wait_for(&self, pin: &str, limit: Duration, ready: impl Fn(&str) -> bool) -> String {
        let end = Instant::now() + limit;
        loop {
            let value = self.getp(pin);
            if ready(&value) {
                return value;
            }
            assert!(
                Instant::now() < end,
                "{pin} is still {value} after {limit:?}\nhalrun's log:\n{}",
                self.log_text()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// Waits up to `limit` until the session's log contains `text` (a component's message
    /// saying it acted); a panic showing the log otherwise.
    pub fn wait_for_log(&self, text: &str, limit: Duration) {
        let end = Instant::now() + limit;
        loop {
            let log = self.log_text();
            if log.contains(text) {
                return;
            }
            assert!(
                Instant::now() < end,
                "halrun's log does not say {text:?} after {limit:?}:\n{log}"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// What the session printed so far (the components' messages).
    pub fn log_text(&self) -> String {
        let mut text = std::fs::read_to_string(&self.log).unwrap_or_default();
        if let Some(dir) = self.log.parent() {
            text.push_str(&std::fs::read_to_string(dir.join("halrun.err")).unwrap_or_default());
        }
        text
    }
}

impl Drop for Hal {
    /// Ends the session: `exit` unloads the components (each releases its drive as it
    /// does when LinuxCNC stops), then `halrun` stops HAL; killed after 10 s.
    fn drop(&mut self) {
        let _ = writeln!(self.commands, "exit");
        let _ = self.commands.flush();
        let end = Instant::now() + Duration::from_secs(10);
        while Instant::now() < end {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn running_as_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

pub use crate::virtual_port::VirtualPort;

/// A fresh folder for one test's HAL session (`vfd-linuxcnc-<name>-<pid>` in the system's
/// temporary folder), emptied first.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vfd-linuxcnc-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Waits up to `limit` for `ready` to hold of the virtual drive behind `drive`; fails with
/// `what`, the raw values of the registers `shown` and halrun's log when it does not.
pub fn wait_on_drive(
    hal: &Hal,
    drive: &VirtualPort,
    shown: &[&str],
    what: &str,
    limit: Duration,
    ready: impl Fn(&vfd_runtime::virtual_drive::VirtualDrive) -> bool,
) {
    let end = Instant::now() + limit;
    loop {
        if ready(&drive.simulator.lock()) {
            return;
        }
        if Instant::now() >= end {
            let sim = drive.simulator.lock();
            let values: Vec<String> = shown
                .iter()
                .map(|code| match sim.raw(code) {
                    Some(raw) => format!("{code} = {raw} ({raw:04X}h)"),
                    None => format!("{code} = none"),
                })
                .collect();
            panic!(
                "the virtual drive never reached: {what} ({})\nhalrun's log:\n{}",
                values.join(", "),
                hal.log_text()
            );
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}
