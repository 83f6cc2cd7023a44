//! Test helper: a private mosquitto per test on a free loopback port (never the system's
//! service), and mosquitto_sub / mosquitto_pub as the peer.

use std::io::Write;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A running mosquitto.
pub struct Broker {
    pub port: u16,
    pub dir: PathBuf,
    extra: String,
    child: Option<Child>,
}

/// The mosquitto binary.
fn mosquitto() -> &'static str {
    [
        "/usr/sbin/mosquitto",
        "/usr/local/sbin/mosquitto",
        "/opt/homebrew/sbin/mosquitto",
    ]
    .into_iter()
    .find(|p| std::path::Path::new(p).exists())
    .unwrap_or("mosquitto")
}

impl Broker {
    /// Starts one with `extra` lines in its configuration (anonymous access when empty).
    pub fn start(name: &str, extra: &str) -> Broker {
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .expect("a free port")
            .port();
        let dir =
            std::env::temp_dir().join(format!("vfd-mqtt-{name}-{}-{port}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let mut broker = Broker {
            port,
            dir,
            extra: extra.to_string(),
            child: None,
        };
        broker.run();
        broker
    }

    /// (Re)starts mosquitto on the same port.
    pub fn run(&mut self) {
        let config = self.dir.join("mosquitto.conf");
        let body = if self.extra.is_empty() {
            "allow_anonymous true\n"
        } else {
            self.extra.as_str()
        };
        let mut file = std::fs::File::create(&config).expect("config");
        write!(
            file,
            "listener {} 127.0.0.1\npersistence false\n{body}\n",
            self.port
        )
        .expect("config");
        let child = Command::new(mosquitto())
            .arg("-c")
            .arg(&config)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("mosquitto starts (install the mosquitto package)");
        self.child = Some(child);
        let deadline = Instant::now() + Duration::from_secs(10);
        while std::net::TcpStream::connect(("127.0.0.1", self.port)).is_err() {
            assert!(
                Instant::now() < deadline,
                "mosquitto did not listen on {}",
                self.port
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// Kills it (no clean shutdown).
    pub fn kill(&mut self) {
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }

    /// The URL to give the client.
    pub fn url(&self) -> String {
        format!("mqtt://127.0.0.1:{}", self.port)
    }

    /// The first message on `topic` (retained ones included) within `wait`, as text.
    pub fn first(&self, topic: &str, wait: u64) -> Option<String> {
        self.sub(topic, 1, wait).pop()
    }

    /// [`Broker::first`] as `user` (name, password).
    pub fn first_as(&self, user: (&str, &str), topic: &str, wait: u64) -> Option<String> {
        self.sub_child_as(Some(user), topic, 1, wait).finish().pop()
    }

    /// `count` messages on `topic` within `wait` seconds.
    pub fn sub(&self, topic: &str, count: usize, wait: u64) -> Vec<String> {
        self.sub_child(topic, count, wait).finish()
    }

    /// A mosquitto_sub started now, to read later.
    pub fn sub_child(&self, topic: &str, count: usize, wait: u64) -> Sub {
        self.sub_child_as(None, topic, count, wait)
    }

    /// [`Broker::sub_child`] as `user` (name, password), or anonymously.
    pub fn sub_child_as(
        &self,
        user: Option<(&str, &str)>,
        topic: &str,
        count: usize,
        wait: u64,
    ) -> Sub {
        let mut command = Command::new("mosquitto_sub");
        if let Some((name, password)) = user {
            command.args(["-u", name, "-P", password]);
        }
        let child = command
            .args(["-h", "127.0.0.1", "-p", &self.port.to_string(), "-t", topic])
            .args(["-C", &count.to_string(), "-W", &wait.to_string(), "-i"])
            .arg(format!("sub-{}-{}", std::process::id(), rand_suffix()))
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("mosquitto_sub");
        std::thread::sleep(Duration::from_millis(300));
        Sub(child)
    }

    /// Publishes `payload` on `topic` (QoS 1), retained or not.
    pub fn publish(&self, topic: &str, payload: &str, retain: bool) {
        self.publish_as(None, topic, payload, retain);
    }

    /// Publishes as `user` (name, password), or anonymously.
    pub fn publish_as(&self, user: Option<(&str, &str)>, topic: &str, payload: &str, retain: bool) {
        let mut command = Command::new("mosquitto_pub");
        if let Some((name, password)) = user {
            command.args(["-u", name, "-P", password]);
        }
        command.args([
            "-h",
            "127.0.0.1",
            "-p",
            &self.port.to_string(),
            "-q",
            "1",
            "-t",
            topic,
            "-m",
            payload,
        ]);
        if retain {
            command.arg("-r");
        }
        let status = command.status().expect("mosquitto_pub");
        assert!(status.success(), "mosquitto_pub failed");
    }
}

fn rand_suffix() -> u128 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos())
}

/// A running mosquitto_sub.
pub struct Sub(Child);

impl Sub {
    /// Its messages (one per line), once it has them all or timed out.
    pub fn finish(self) -> Vec<String> {
        let output = self.0.wait_with_output().expect("mosquitto_sub output");
        String::from_utf8_lossy(&output.stdout)
            .lines()
            .map(str::to_string)
            .collect()
    }
}

impl Drop for Broker {
    fn drop(&mut self) {
        self.kill();
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}
