//! Finds whether mosquitto (the MQTT broker the `serve::mqtt` tests start) is installed: if
//! not, those tests are built `#[ignore]`d with the reason (`cfg(missing_mosquitto)`), so
//! they show as ignored, never as `ok`. Under CI (`CI` set) nothing is ignored: a missing
//! mosquitto fails them.

fn main() {
    println!("cargo::rustc-check-cfg=cfg(missing_mosquitto)");
    println!("cargo:rerun-if-env-changed=CI");
    println!("cargo:rerun-if-env-changed=PATH");
    if std::env::var_os("CI").is_some() {
        return;
    }
    let found = [
        "/usr/sbin/mosquitto",
        "/usr/local/sbin/mosquitto",
        "/opt/homebrew/sbin/mosquitto",
    ]
    .iter()
    .any(|p| std::path::Path::new(p).exists())
        || std::process::Command::new("mosquitto")
            .arg("-h")
            .output()
            .is_ok();
    let tools = std::process::Command::new("mosquitto_sub")
        .arg("--help")
        .output()
        .is_ok();
    if !(found && tools) {
        println!("cargo:rustc-cfg=missing_mosquitto");
    }
}
