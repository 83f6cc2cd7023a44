//! How to reach the broker: the `--mqtt` URL, the prefix, the client id, the credentials
//! (from the environment or a file, never the command line) and the TLS roots.

use crate::Failure;
use rustls::pki_types::pem::PemObject;
use rustls::pki_types::CertificateDer;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The user name's environment variable.
pub const USERNAME_VARIABLE: &str = "VFD_MQTT_USERNAME";
/// The password's environment variable.
pub const PASSWORD_VARIABLE: &str = "VFD_MQTT_PASSWORD";
/// The environment variable naming a file that holds the password.
pub const PASSWORD_FILE_VARIABLE: &str = "VFD_MQTT_PASSWORD_FILE";

/// Everything `vfd serve --mqtt` needs to publish.
#[derive(Debug, Clone)]
pub struct MqttOptions {
    /// The broker.
    pub url: BrokerUrl,
    /// The first topic level(s) (`vfd`); no `+`, `#`, and no leading or trailing `/`.
    pub prefix: String,
    /// The MQTT client id. It must stay the same across restarts (the broker keeps the
    /// session, so `set` messages sent while the service is down are delivered) and differ
    /// between services on one broker.
    pub client_id: String,
    /// Publish Home Assistant discovery configs.
    pub ha_discovery: bool,
    /// User name and password, if the broker wants them.
    pub credentials: Option<Credentials>,
    /// An extra CA certificate (PEM) for `mqtts://`; the system's roots are always trusted.
    pub ca_file: Option<PathBuf>,
}

impl MqttOptions {
    /// Options for `url` with the defaults: prefix `vfd`, client id `vfd-serve-HOST-PREFIX`,
    /// credentials from the environment (`VFD_MQTT_USERNAME`, `VFD_MQTT_PASSWORD` or
    /// `VFD_MQTT_PASSWORD_FILE`, or `password_file` when given), no discovery.
    pub fn new(url: &str, password_file: Option<&Path>) -> Result<MqttOptions, Failure> {
        let prefix = "vfd".to_string();
        Ok(MqttOptions {
            url: parse_url(url)?,
            client_id: default_client_id(&prefix),
            prefix,
            ha_discovery: false,
            credentials: Credentials::from_env(password_file)?,
            ca_file: None,
        })
    }

    /// Sets the prefix, checked (and the default client id with it).
    pub fn with_prefix(mut self, prefix: &str) -> Result<MqttOptions, Failure> {
        let trimmed = prefix.trim_matches('/');
        if trimmed.is_empty() || trimmed.contains(['+', '#']) || trimmed.contains("//") {
            return Err(Failure::new(format!(
                "MQTT prefix '{prefix}' is not usable as the first topic levels"
            ))
            .hint(
                "use letters, digits, '-', '_' and '/' between levels, e.g. 'vfd' or 'site1/vfd'",
            ));
        }
        if self.client_id == default_client_id(&self.prefix) {
            self.client_id = default_client_id(trimmed);
        }
        self.prefix = trimmed.to_string();
        Ok(self)
    }
}

/// `vfd-serve-HOST-PREFIX` (the prefix's `/` as `-`): stable across restarts on one host.
fn default_client_id(prefix: &str) -> String {
    let host = std::fs::read_to_string("/etc/hostname")
        .ok()
        .map(|h| h.trim().to_string())
        .filter(|h| !h.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .or_else(|| std::env::var("COMPUTERNAME").ok())
        .unwrap_or_else(|| "host".to_string());
    format!("vfd-serve-{host}-{}", prefix.replace('/', "-"))
}

/// A user name and password. Its `Debug` form hides the password.
#[derive(Clone)]
pub struct Credentials {
    /// The user name.
    pub username: String,
    /// The password.
    pub password: String,
}

impl std::fmt::Debug for Credentials {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Credentials")
            .field("username", &self.username)
            .field("password", &"(hidden)")
            .finish()
    }
}

impl Credentials {
    /// From the environment: `VFD_MQTT_USERNAME`, and the password from `password_file`,
    /// else the file `VFD_MQTT_PASSWORD_FILE` names, else `VFD_MQTT_PASSWORD` (the file's
    /// first line). `None` when no user name is set; a password without one is an error.
    pub fn from_env(password_file: Option<&Path>) -> Result<Option<Credentials>, Failure> {
        let file = password_file
            .map(Path::to_path_buf)
            .or_else(|| std::env::var_os(PASSWORD_FILE_VARIABLE).map(PathBuf::from));
        Credentials::resolve(
            std::env::var(USERNAME_VARIABLE).ok(),
            file.as_deref(),
            std::env::var(PASSWORD_VARIABLE).ok(),
        )
    }

    /// The credentials from a user name, a password file (preferred) or a password.
    fn resolve(
        username: Option<String>,
        file: Option<&Path>,
        password: Option<String>,
    ) -> Result<Option<Credentials>, Failure> {
        let username = username.filter(|u| !u.is_empty());
        let password = match file {
            Some(file) => Some(
                std::fs::read_to_string(file)
                    .map_err(|e| {
                        Failure::new(format!(
                            "cannot read the MQTT password file {}: {e}",
                            file.display()
                        ))
                    })?
                    .lines()
                    .next()
                    .unwrap_or_default()
                    .to_string(),
            ),
            None => password,
        };
        match (username, password) {
            (Some(username), password) => Ok(Some(Credentials {
                username,
                password: password.unwrap_or_default(),
            })),
            (None, Some(_)) => Err(Failure::new(format!(
                "an MQTT password is given but no user name ({USERNAME_VARIABLE} is not set)"
            ))),
            (None, None) => Ok(None),
        }
    }
}

/// A parsed `--mqtt` URL.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BrokerUrl {
    /// `mqtts://`: TLS.
    pub tls: bool,
    /// Host name or address.
    pub host: String,
    /// Port (default 1883, or 8883 with TLS).
    pub port: u16,
}

impl std::fmt::Display for BrokerUrl {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let scheme = if self.tls { "mqtts" } else { "mqtt" };
        if self.host.contains(':') {
            write!(f, "{scheme}://[{}]:{}", self.host, self.port)
        } else {
            write!(f, "{scheme}://{}:{}", self.host, self.port)
        }
    }
}

/// Parses `mqtt://HOST[:PORT]` or `mqtts://HOST[:PORT]` (an IPv6 address in brackets). A
/// user or password in the URL is refused: credentials come from the environment.
pub fn parse_url(url: &str) -> Result<BrokerUrl, Failure> {
    let hint = "write mqtt://HOST[:1883] or mqtts://HOST[:8883]";
    let (tls, rest) = if let Some(rest) = url.strip_prefix("mqtt://") {
        (false, rest)
    } else if let Some(rest) = url.strip_prefix("mqtts://") {
        (true, rest)
    } else {
        let scheme = url.split_once("://").map_or("(none)", |(s, _)| s);
        return Err(Failure::new(format!("MQTT URL: unknown scheme '{scheme}'")).hint(hint));
    };
    let rest = rest.trim_end_matches('/');
    if rest.contains('@') {
        return Err(Failure::new(
            "MQTT URL: a user or password in the URL is not accepted (it would show in the process list)",
        )
        .hint(format!(
            "set {USERNAME_VARIABLE} and {PASSWORD_VARIABLE} (or {PASSWORD_FILE_VARIABLE}, --mqtt-password-file)"
        )));
    }
    if rest.contains('/') {
        return Err(Failure::new("MQTT URL: a path is not accepted after the host").hint(hint));
    }
    let (host, port) = if let Some(bracketed) = rest.strip_prefix('[') {
        let (host, after) = bracketed.split_once(']').ok_or_else(|| {
            Failure::new("MQTT URL: '[' without ']' around the address").hint(hint)
        })?;
        (host, after.strip_prefix(':'))
    } else {
        match rest.rsplit_once(':') {
            Some((host, port)) => (host, Some(port)),
            None => (rest, None),
        }
    };
    if host.is_empty() {
        return Err(Failure::new("MQTT URL: no host").hint(hint));
    }
    let port = match port {
        None => {
            if tls {
                8883
            } else {
                1883
            }
        }
        Some(text) => match text.parse::<u16>() {
            Ok(port) if port > 0 => port,
            _ => {
                return Err(Failure::new(format!(
                    "MQTT URL: port '{text}' is not a number from 1 to 65535"
                ))
                .hint(hint))
            }
        },
    };
    Ok(BrokerUrl {
        tls,
        host: host.to_string(),
        port,
    })
}

/// The TLS configuration for `mqtts://`: ring as the crypto provider, the system's roots
/// and `ca_file`'s certificates.
pub fn tls_config(ca_file: Option<&Path>) -> Result<Arc<rustls::ClientConfig>, Failure> {
    let mut roots = rustls::RootCertStore::empty();
    let native = rustls_native_certs::load_native_certs();
    for error in &native.errors {
        log::debug!("system CA certificates: {error}");
    }
    roots.add_parsable_certificates(native.certs);
    if let Some(file) = ca_file {
        let text = std::fs::read(file).map_err(|e| {
            Failure::new(format!("cannot read the CA file {}: {e}", file.display()))
        })?;
        let mut added = 0;
        for cert in CertificateDer::pem_slice_iter(&text) {
            let cert = cert.map_err(|e| {
                Failure::new(format!(
                    "CA file {}: not PEM certificates: {e}",
                    file.display()
                ))
            })?;
            roots
                .add(cert)
                .map_err(|e| Failure::new(format!("CA file {}: {e}", file.display())))?;
            added += 1;
        }
        if added == 0 {
            return Err(
                Failure::new(format!("CA file {}: no certificate in it", file.display()))
                    .hint("give a PEM file with -----BEGIN CERTIFICATE----- blocks"),
            );
        }
    }
    if roots.is_empty() {
        return Err(
            Failure::new("mqtts: no CA certificate found on this system")
                .hint("give the broker's CA with --mqtt-ca-file"),
        );
    }
    let config = rustls::ClientConfig::builder_with_provider(Arc::new(
        rustls::crypto::ring::default_provider(),
    ))
    .with_safe_default_protocol_versions()
    .map_err(|e| Failure::new(format!("TLS: {e}")))?
    .with_root_certificates(roots)
    .with_no_client_auth();
    Ok(Arc::new(config))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn urls_parse_with_default_ports() {
        let url = parse_url("mqtt://broker.local").unwrap();
        assert_eq!(
            (url.tls, url.host.as_str(), url.port),
            (false, "broker.local", 1883)
        );
        let url = parse_url("mqtts://10.0.0.2").unwrap();
        assert_eq!((url.tls, url.port), (true, 8883));
        let url = parse_url("mqtt://127.0.0.1:1884/").unwrap();
        assert_eq!(url.port, 1884);
        let url = parse_url("mqtt://[::1]:1885").unwrap();
        assert_eq!((url.host.as_str(), url.port), ("::1", 1885));
        assert_eq!(url.to_string(), "mqtt://[::1]:1885");
    }

    #[test]
    fn bad_urls_say_what_is_wrong() {
        let message = |url: &str| parse_url(url).unwrap_err().message;
        assert!(message("http://x").contains("unknown scheme 'http'"));
        assert!(message("broker:1883").contains("unknown scheme '(none)'"));
        assert!(message("mqtt://:1883").contains("no host"));
        assert!(message("mqtt://h:99999").contains("port '99999'"));
        assert!(message("mqtt://h:x").contains("port 'x'"));
        let secret = message("mqtt://user:hunter2@h");
        assert!(secret.contains("not accepted") && !secret.contains("hunter2"));
    }

    #[test]
    fn credentials_come_from_a_password_file_first_and_are_never_in_errors() {
        let dir = std::env::temp_dir().join(format!("vfd-mqtt-cred-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("password");
        std::fs::write(&file, "from-file-pw\nignored\n").unwrap();
        let found = Credentials::resolve(Some("svc".into()), Some(&file), Some("env-pw".into()))
            .unwrap_or_else(|f| panic!("{}", f.message))
            .expect("credentials");
        assert_eq!(
            (found.username.as_str(), found.password.as_str()),
            ("svc", "from-file-pw")
        );
        let found = Credentials::resolve(Some("svc".into()), None, Some("env-pw".into()))
            .unwrap_or_else(|f| panic!("{}", f.message))
            .expect("credentials");
        assert_eq!(found.password, "env-pw");
        let failure = Credentials::resolve(None, None, Some("env-pw".into())).unwrap_err();
        assert!(failure.message.contains(USERNAME_VARIABLE) && !failure.message.contains("env-pw"));
        let failure =
            Credentials::resolve(Some("svc".into()), Some(&dir.join("none")), None).unwrap_err();
        assert!(failure
            .message
            .contains("cannot read the MQTT password file"));
        assert!(Credentials::resolve(None, None, None)
            .unwrap_or_else(|f| panic!("{}", f.message))
            .is_none());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn credentials_hide_the_password_in_debug() {
        let credentials = Credentials {
            username: "svc".into(),
            password: "hunter2".into(),
        };
        assert!(!format!("{credentials:?}").contains("hunter2"));
    }
}
