//! Test helper: a private mosquitto per test.
