//! `mqtts://` against a private mosquitto with a certificate of a CA made for the test:
//! the CA given with `--mqtt-ca-file` is trusted, and a failed handshake says what to check
//! (the CA file for an unknown CA, the host name for a certificate of another name, TLS
//! itself for a plain listener), never "is the broker running".

use super::broker::Broker;
use super::test_plant::plant;
use super::tests::options;
use super::Mqtt;
use vfd_bus::service::event::WriteRouter;

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients)"
)]
fn mqtts_trusts_the_given_ca_and_names_the_ca_or_the_host_when_the_handshake_fails() {
    let dir = std::env::temp_dir().join(format!("vfd-mqtt-tls-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let openssl = |args: &[&str]| {
        let status = std::process::Command::new("openssl")
            .current_dir(&dir)
            .args(args)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .status();
        assert!(
            status.is_ok_and(|s| s.success()),
            "openssl {args:?} failed (is openssl installed?)"
        );
    };
    let ec = [
        "-newkey",
        "ec",
        "-pkeyopt",
        "ec_paramgen_curve:prime256v1",
        "-nodes",
    ];
    openssl(
        &[
            &["req", "-x509"][..],
            &ec,
            &[
                "-keyout",
                "ca.key",
                "-out",
                "ca.crt",
                "-days",
                "2",
                "-subj",
                "/CN=vfd test CA",
            ],
        ]
        .concat(),
    );
    openssl(
        &[
            &["req"][..],
            &ec,
            &[
                "-keyout",
                "server.key",
                "-out",
                "server.csr",
                "-subj",
                "/CN=127.0.0.1",
            ],
        ]
        .concat(),
    );
    std::fs::write(
        dir.join("ext.cnf"),
        "subjectAltName=IP:127.0.0.1\nbasicConstraints=CA:FALSE\nextendedKeyUsage=serverAuth\n",
    )
    .unwrap();
    openssl(&[
        "x509",
        "-req",
        "-in",
        "server.csr",
        "-CA",
        "ca.crt",
        "-CAkey",
        "ca.key",
        "-CAcreateserial",
        "-out",
        "server.crt",
        "-days",
        "2",
        "-extfile",
        "ext.cnf",
    ]);
    // Run as root, mosquitto drops to its own user, which must read the key.
    for file in ["server.key", "server.crt", "ca.crt"] {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(dir.join(file), std::fs::Permissions::from_mode(0o644)).unwrap();
    }
    let broker = Broker::start(
        "tls",
        &format!(
            "allow_anonymous true\ncafile {0}/ca.crt\ncertfile {0}/server.crt\nkeyfile {0}/server.key\n",
            dir.display()
        ),
    );
    let mut options = options(&broker, "tls");
    options.url = super::parse_url(&format!("mqtts://127.0.0.1:{}", broker.port))
        .unwrap_or_else(|f| panic!("{}", f.message));
    options.ca_file = Some(dir.join("ca.crt"));
    let mqtt = Mqtt::connect(&options, &plant(), WriteRouter::default())
        .unwrap_or_else(|f| panic!("{}", f.message));
    mqtt.shutdown();
    // The system's roots do not know the test CA: the hint is about the CA file.
    options.ca_file = None;
    let failure = Mqtt::connect(&options, &plant(), WriteRouter::default())
        .err()
        .expect("an unknown CA refused");
    let hint = failure.hint.clone().unwrap_or_default();
    assert!(
        failure.message.contains("TLS handshake"),
        "{}",
        failure.message
    );
    assert!(
        hint.contains("--mqtt-ca-file") && hint.contains("not signed by a CA"),
        "{hint}"
    );
    assert!(!hint.contains("is the broker running"), "{hint}");
    // The right CA, the wrong name: the certificate is for 127.0.0.1, not localhost.
    options.ca_file = Some(dir.join("ca.crt"));
    options.url = super::parse_url(&format!("mqtts://localhost:{}", broker.port))
        .unwrap_or_else(|f| panic!("{}", f.message));
    let failure = Mqtt::connect(&options, &plant(), WriteRouter::default())
        .err()
        .expect("a certificate for another name refused");
    let hint = failure.hint.clone().unwrap_or_default();
    assert!(
        failure.message.contains("TLS handshake"),
        "{}",
        failure.message
    );
    assert!(
        hint.contains("not for the host name `localhost`"),
        "{}: {hint}",
        failure.message
    );
    assert!(!hint.contains("is the broker running"), "{hint}");
    // mqtts:// to a plain listener: the hint asks whether the port speaks TLS.
    let plain = Broker::start("tls-plain", "");
    options.url = super::parse_url(&format!("mqtts://127.0.0.1:{}", plain.port))
        .unwrap_or_else(|f| panic!("{}", f.message));
    let failure = Mqtt::connect(&options, &plant(), WriteRouter::default())
        .err()
        .expect("no TLS there");
    let hint = failure.hint.clone().unwrap_or_default();
    assert!(hint.contains("speak TLS"), "{}: {hint}", failure.message);
    let _ = std::fs::remove_dir_all(&dir);
}
