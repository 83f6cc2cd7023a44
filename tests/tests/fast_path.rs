//! The fast path against the interpreter: every protocol of every described drive (each
//! variant too), every command, through both paths with the same bytes. The fast path is
//! the layouts' plans ([`vfd_runtime::plan`]): compiled by the generator into the
//! generated layouts, or run step by step for a plan computed at run time. The interpreter
//! is the same protocol with its plans taken out ([`Protocol::without_plans`]). Requests must
//! encode to the same bytes or the same error; replies (the manual's frames, frames made
//! by the interpreter, and their prefixes, corruptions, noise and trailing bytes) must
//! decode to the same outcome through `decode_reply`, `find_reply`, `decode_reply_exact`,
//! `search_reply` and `decode_request`; and where a plan decodes a frame on its own, the
//! interpreter must decode the same values.

use std::collections::BTreeMap;
use vfd_runtime::codec::{self, DecodeStatus};
use vfd_runtime::plan::FramePlan;
use vfd_runtime::protocol::{CommandSpec, Expectation};
use vfd_runtime::{
    CommandKind, DataType, FrameLayout, FrameValues, Protocol, Request, Roles, Space,
};
use vfd_tests::random::Random;

/// Every protocol of every described drive, in each of its variants, named `drive/id`.
fn protocols() -> Vec<(String, &'static Protocol)> {
    let mut all = Vec::new();
    for drive in vfd_drives::ALL_DRIVES.iter() {
        for protocol in drive.protocols.iter() {
            for variant in protocol.all_variants() {
                let name = format!(
                    "{}/{}{}",
                    drive.id,
                    variant.id,
                    variant
                        .variant_id()
                        .map(|v| format!(" ({v})"))
                        .unwrap_or_default()
                );
                all.push((name, variant));
            }
        }
    }
    all
}

/// The manual's frames (requests and replies) of every example, by `drive/protocol id`.
fn golden_frames() -> BTreeMap<String, Vec<Vec<u8>>> {
    let generated = vfd_codegen::Builder::new()
        .drives_in("../drives")
        .expect("drives/ is readable")
        .display_root("..")
        .generate_in_memory()
        .unwrap_or_else(|error| panic!("the drive files do not generate:\n{error}"));
    let mut frames: BTreeMap<String, Vec<Vec<u8>>> = BTreeMap::new();
    for drive in &generated.drives {
        for example in &drive.ir.examples {
            let key = format!("{}/{}", drive.ir.id, example.protocol);
            for frame in example.request.iter().chain(example.reply.iter()) {
                frames
                    .entry(key.clone())
                    .or_default()
                    .push(frame.bytes.clone());
            }
        }
    }
    frames
}

/// The layouts of `protocol`: every command's request, reply and follow-ups, and the error
/// reply.
fn layouts(protocol: &Protocol) -> Vec<&FrameLayout> {
    let mut layouts = Vec::new();
    for command in protocol.commands.iter() {
        layouts.push(&command.request);
        layouts.push(&command.reply);
        if let Some(follow_up) = &command.follow_up {
            layouts.push(&follow_up.ok);
            layouts.push(&follow_up.again);
        }
    }
    layouts.extend(protocol.error_reply.as_ref());
    layouts
}

/// The data types a command carries (any, when it lists none).
fn data_types(command: &CommandSpec) -> Vec<DataType> {
    if command.data_types.is_empty() {
        vec![DataType::Word, DataType::DoubleWord, DataType::Bit]
    } else {
        command.data_types.to_vec()
    }
}

/// Role values to build frames with: the command's codes (and their lower case), a few
/// stations, registers and data.
fn role_sets(protocol: &Protocol, command: &CommandSpec, random: &mut Random) -> Vec<Roles> {
    let mut codes = vec![command.code];
    codes.extend(command.reply_codes.iter().copied());
    codes.extend(command.error_code);
    if let Ok(letter) = u8::try_from(command.code) {
        if letter.is_ascii_uppercase() {
            codes.push(u32::from(letter.to_ascii_lowercase()));
        }
    }
    let (min, max) = protocol.address_range;
    let mut sets = Vec::new();
    for &code in &codes {
        for address in [None, Some(min), Some(max), Some(1)] {
            let register = random.next_u64() as u32 & 0xFFFF;
            let data = [0, 1, 0x1770, 0xFFFF, random.next_u64() as u32][random.below(5)];
            sets.push(Roles {
                address: address.map(u32::from),
                command: Some(code),
                register: Some(register),
                index: Some(random.below(3) as u32),
                data: Some(data),
                error_code: Some(random.below(5) as u32),
                process_1: Some(random.next_u64() as u32 & 0xFFFF),
                process_2: Some(random.next_u64() as u32 & 0xFFFF),
                decimals: Some(random.below(4) as u32),
            });
        }
    }
    sets
}

/// Frames of `layout` the interpreter writes for `roles`, each data size a command carries.
fn frames_of(
    protocol: &Protocol,
    layout: &FrameLayout,
    roles: &Roles,
    sizes: &[u8],
) -> Vec<Vec<u8>> {
    let mut frames = Vec::new();
    for &data_size in sizes {
        let mut values = FrameValues {
            data_size,
            ..FrameValues::default()
        };
        for name in protocol.default_optional_parts.iter() {
            values.include(layout, &[name]);
        }
        values.fill(layout, roles);
        let mut out = [0u8; 600];
        if let Ok(len) = codec::encode(layout, &values, &mut out) {
            frames.push(out[..len].to_vec());
        }
    }
    frames
}

/// `frame`, and what the line may make of it: every proper prefix, each byte changed,
/// noise before it, bytes after it, and the frame twice.
fn shaken(frame: &[u8], random: &mut Random) -> Vec<Vec<u8>> {
    let mut inputs = vec![frame.to_vec()];
    for len in 0..frame.len() {
        inputs.push(frame[..len].to_vec());
    }
    for at in 0..frame.len() {
        for change in [0x01u8, 0x20, 0x80, 0xFF] {
            let mut changed = frame.to_vec();
            changed[at] ^= change;
            inputs.push(changed);
        }
    }
    let noise = random.next_u64() as u8;
    inputs.push([&[noise][..], frame].concat());
    inputs.push([&[0x00, 0xFF][..], frame].concat());
    inputs.push([frame, &[noise][..]].concat());
    inputs.push([frame, frame].concat());
    inputs
}

/// Runs every decoder of both protocols on `bytes` and asserts the same outcome; returns
/// how many reply layouts the plans decoded on their own.
fn assert_decoders_agree(
    name: &str,
    fast: &'static Protocol,
    slow: &Protocol,
    bytes: &[u8],
) -> usize {
    let context = || format!("{name}, bytes {bytes:02X?}");
    assert_eq!(
        fast.decode_request(bytes),
        slow.decode_request(bytes),
        "decode_request: {}",
        context()
    );
    assert_eq!(
        fast.decode_reply(None, bytes),
        slow.decode_reply(None, bytes),
        "decode_reply(None): {}",
        context()
    );
    assert_eq!(
        fast.find_reply(None, bytes),
        slow.find_reply(None, bytes),
        "find_reply(None): {}",
        context()
    );
    let mut planned = 0;
    for (index, (a, b)) in fast.commands.iter().zip(slow.commands.iter()).enumerate() {
        let command = || format!("command {index} ({}), {}", a.code_label(), context());
        assert_eq!(
            fast.decode_reply(Some(a), bytes),
            slow.decode_reply(Some(b), bytes),
            "decode_reply: {}",
            command()
        );
        assert_eq!(
            fast.find_reply(Some(a), bytes),
            slow.find_reply(Some(b), bytes),
            "find_reply: {}",
            command()
        );
        assert_eq!(
            fast.decode_reply_exact(Some(a), bytes),
            slow.decode_reply_exact(Some(b), bytes),
            "decode_reply_exact: {}",
            command()
        );
        let expectations = [
            Expectation::default(),
            Expectation {
                address: Some(1),
                data_size: Some(4),
                ..Expectation::default()
            },
        ];
        for expectation in &expectations {
            assert_eq!(
                fast.search_reply(a, expectation, bytes),
                slow.search_reply(b, expectation, bytes),
                "search_reply({expectation:?}): {}",
                command()
            );
        }
        if a.reply
            .plan
            .as_ref()
            .is_some_and(|plan| plan.decode(&a.reply, bytes).is_some())
        {
            planned += 1;
        }
    }
    planned
}

/// Where a plan decodes `bytes` with `layout`, the interpreter decodes the same values and
/// length, the roles are the values' roles, and the plan's compiled functions and its
/// steps agree.
fn assert_plan_agrees(name: &str, layout: &FrameLayout, bytes: &[u8]) {
    let Some(plan) = &layout.plan else {
        return;
    };
    let fast = plan.decode(layout, bytes);
    assert_eq!(
        fast,
        plan.decode_steps(layout, bytes),
        "{name}, layout {}: compiled and step-by-step plans disagree on {bytes:02X?}",
        layout.name
    );
    if let Some(frame) = fast {
        assert_eq!(
            codec::decode(layout, bytes),
            Ok(DecodeStatus::Complete {
                values: frame.values,
                len: frame.len
            }),
            "{name}, layout {}: the plan decodes {bytes:02X?}, the interpreter otherwise",
            layout.name
        );
        assert_eq!(
            frame.roles,
            frame.values.roles(layout),
            "{name}, {}",
            layout.name
        );
    }
}

#[test]
fn generated_layouts_hold_the_plan_of_their_parts_compiled() {
    let generated: Vec<&'static Protocol> = vfd_drives::ALL_DRIVES
        .iter()
        .flat_map(|drive| drive.protocols.iter().copied())
        .collect();
    let mut compiled = 0;
    for (name, protocol) in protocols() {
        let is_static = generated.iter().any(|p| std::ptr::eq(*p, protocol));
        for layout in layouts(protocol) {
            assert_eq!(
                layout.plan,
                FramePlan::of(layout),
                "{name}, layout {}: the plan is not the one its parts make",
                layout.name
            );
            if let Some(plan) = &layout.plan {
                // Generated layouts hold compiled plans; a variant built at run time (other
                // literal bytes) has its plan computed then, run step by step.
                assert_eq!(
                    plan.compiled.is_some(),
                    is_static,
                    "{name}, layout {}",
                    layout.name
                );
                compiled += usize::from(is_static);
            }
        }
    }
    assert!(compiled > 20, "only {compiled} compiled plans");
    // The Modbus RTU exchanges the codec benchmark measures take the fast path.
    let modbus = vfd_drives::fc51::protocols::MODBUS.protocol();
    let benchmarked: Vec<_> = modbus
        .commands
        .iter()
        .filter(|c| [0x03, 0x06].contains(&c.code))
        .collect();
    assert_eq!(benchmarked.len(), 2, "Modbus 03 and 06");
    for command in benchmarked {
        assert!(command
            .request
            .plan
            .as_ref()
            .is_some_and(|p| p.compiled.is_some()));
        assert!(command
            .reply
            .plan
            .as_ref()
            .is_some_and(|p| p.compiled.is_some()));
    }
}

#[test]
fn plans_computed_at_run_time_are_the_generated_ones_without_compiled_functions() {
    let generated = vfd_codegen::Builder::new()
        .drives_in("../drives")
        .expect("drives/ is readable")
        .display_root("..")
        .generate_in_memory()
        .unwrap_or_else(|error| panic!("the drive files do not generate:\n{error}"));
    let mut compared = 0;
    for drive in &generated.drives {
        let statics = vfd_drives::drive(&drive.ir.id).expect("generated drive");
        for file in &drive.ir.protocol_files {
            for layout in &file.layouts {
                assert!(layout.plan.as_ref().is_none_or(|p| p.compiled.is_none()));
                for protocol in statics.protocols.iter() {
                    for generated_layout in layouts(protocol) {
                        if generated_layout == layout {
                            assert_eq!(generated_layout.plan, layout.plan, "{}", layout.name);
                            compared += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(compared > 20, "only {compared} layouts compared");
}

#[test]
fn requests_encode_alike_through_both_paths() {
    let mut random = Random(0x5EED_0001);
    let mut planned_layout_encodes = 0;
    let mut plan_encodes = 0;
    for (name, fast) in protocols() {
        let slow = fast.without_plans();
        let (min, max) = fast.address_range;
        let addresses = [
            None,
            Some(min),
            Some(max),
            Some(max.saturating_add(1)),
            Some(0),
        ];
        for command in fast.commands.iter() {
            for data_type in data_types(command) {
                for _ in 0..6 {
                    let register = [0u16, 1, 0x0BD5, 0xFA01, 0xFFFF, random.next_u64() as u16]
                        [random.below(6)];
                    let data = [
                        0u32,
                        1,
                        0x1770,
                        0xFFFF,
                        0x1_0000,
                        u32::MAX,
                        random.next_u64() as u32,
                    ][random.below(7)];
                    let base = Request::raw(command.kind, register, data)
                        .in_space(command.space)
                        .with_data_type(data_type);
                    let requests = [
                        base,
                        Request {
                            wire_register: true,
                            ..base
                        },
                        Request {
                            command: Some(command.code),
                            wire_register: true,
                            index: Some(random.below(4) as u16),
                            process: Some([0x047C, 0x2000]),
                            ..base
                        },
                    ];
                    for request in &requests {
                        for &address in &addresses {
                            for size in [64usize, 8, 3] {
                                let (mut a, mut b) = (vec![0u8; size], vec![0u8; size]);
                                let fast_result = fast.encode_request(request, address, &mut a);
                                let slow_result = slow.encode_request(request, address, &mut b);
                                assert_eq!(
                                    fast_result, slow_result,
                                    "{name}: {request:?} to {address:?} in {size} bytes"
                                );
                                if let Ok(len) = fast_result {
                                    assert_eq!(a[..len], b[..len], "{name}: {request:?}");
                                    if command.request.plan.is_some() {
                                        planned_layout_encodes += 1;
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        // Plans alone, from role values: compiled, step by step, and the interpreter.
        for command in fast.commands.iter() {
            let layout = &command.request;
            let Some(plan) = &layout.plan else { continue };
            for roles in role_sets(fast, command, &mut random) {
                for data_size in [0u8, 1, 2, 4, 6] {
                    let (mut a, mut b) = ([0u8; 64], [0u8; 64]);
                    let include = &fast.default_optional_parts;
                    let compiled = plan.encode(layout, &roles, data_size, include, &mut a);
                    let steps = plan.encode_steps(layout, &roles, data_size, include, &mut b);
                    assert_eq!(compiled, steps, "{name}, {}: {roles:?}", layout.name);
                    if let Some(len) = compiled {
                        plan_encodes += 1;
                        assert_eq!(a[..len], b[..len]);
                        let expected = frames_of(fast, layout, &roles, &[data_size]);
                        assert_eq!(
                            expected,
                            vec![a[..len].to_vec()],
                            "{name}, {}: {roles:?}, {data_size} data bytes",
                            layout.name
                        );
                    }
                }
            }
        }
    }
    eprintln!(
        "requests of planned layouts encoded both ways: {planned_layout_encodes}; \
         frames the plans encoded alone: {plan_encodes}"
    );
    assert!(
        planned_layout_encodes > 1000,
        "only {planned_layout_encodes} requests of planned layouts"
    );
    // The plans themselves wrote frames (compiled and step by step agreeing with the
    // interpreter): not a comparison of `None` with `None` only.
    assert!(
        plan_encodes > 500,
        "only {plan_encodes} frames the plans wrote"
    );
}

#[test]
fn replies_decode_alike_through_both_paths() {
    let golden = golden_frames();
    let mut used_golden = std::collections::BTreeSet::new();
    let mut random = Random(0x5EED_0002);
    let mut planned = 0;
    let mut inputs_tried = 0;
    for (name, fast) in protocols() {
        let slow = fast.without_plans();
        let key = name.split(' ').next().unwrap_or_default().to_owned();
        let mut frames: Vec<Vec<u8>> = golden.get(&key).cloned().unwrap_or_default();
        if golden.contains_key(&key) {
            used_golden.insert(key.clone());
        }
        for command in fast.commands.iter() {
            let sizes: Vec<u8> = data_types(command).iter().map(|t| t.size()).collect();
            for roles in role_sets(fast, command, &mut random) {
                frames.extend(frames_of(fast, &command.reply, &roles, &sizes));
                frames.extend(frames_of(fast, &command.request, &roles, &sizes));
                if let Some(follow_up) = &command.follow_up {
                    frames.extend(frames_of(fast, &follow_up.ok, &roles, &[0]));
                }
            }
        }
        if let Some(error_reply) = &fast.error_reply {
            for roles in role_sets(fast, &fast.commands[0], &mut random) {
                frames.extend(frames_of(fast, error_reply, &roles, &[0]));
            }
        }
        frames.sort();
        frames.dedup();
        let mut seen = std::collections::BTreeSet::new();
        for frame in &frames {
            for bytes in shaken(frame, &mut random) {
                if !seen.insert(bytes.clone()) {
                    continue;
                }
                inputs_tried += 1;
                planned += assert_decoders_agree(&name, fast, &slow, &bytes);
                for layout in layouts(fast) {
                    assert_plan_agrees(&name, layout, &bytes);
                }
            }
        }
    }
    eprintln!("{inputs_tried} inputs; replies decoded by plans: {planned}");
    assert!(inputs_tried > 10_000, "only {inputs_tried} inputs");
    assert!(planned > 1_000, "the plans decoded only {planned} replies");
    // Every manual's frames were among the inputs (a key that stopped matching would
    // silently leave them out).
    let unused: Vec<&String> = golden
        .keys()
        .filter(|k| !used_golden.contains(*k))
        .collect();
    assert!(unused.is_empty(), "manual frames never tried: {unused:?}");
}

#[test]
fn the_benchmarked_modbus_frames_take_the_fast_path_and_decode_alike() {
    let fast = vfd_drives::fc51::protocols::MODBUS.protocol();
    let slow = fast.without_plans();
    let read = Request {
        wire_register: true,
        ..Request::raw(CommandKind::Read, 0x0BD5, 0).with_data_type(DataType::DoubleWord)
    };
    let (mut a, mut b) = ([0u8; 16], [0u8; 16]);
    let len = fast
        .encode_request(&read, Some(1), &mut a)
        .expect("encodes");
    assert_eq!(len, 8);
    assert_eq!(a[..6], [0x01, 0x03, 0x0B, 0xD5, 0x00, 0x02]);
    assert_eq!(slow.encode_request(&read, Some(1), &mut b), Ok(len));
    assert_eq!(a, b);
    let reply = [0x01, 0x03, 0x04, 0x00, 0x00, 0xEA, 0x60, 0xB5, 0x7B];
    let command = fast
        .command_for(CommandKind::Read, Space::Parameter, DataType::DoubleWord)
        .expect("03");
    let plan = command.reply.plan.as_ref().expect("planned");
    let frame = plan
        .decode(&command.reply, &reply)
        .expect("the plan decodes it");
    assert_eq!(frame.roles.data, Some(0xEA60));
    assert_eq!(frame.len, 9);
    assert_decoders_agree("fc51/modbus", fast, &slow, &reply);
    let write = [0x01, 0x06, 0x03, 0xF1, 0x00, 0x01, 0x19, 0xBD];
    assert_decoders_agree("fc51/modbus", fast, &slow, &write);
    // An exception reply and a wrong CRC are the interpreter's: the plan passes them on.
    let exception = [0x01, 0x83, 0x02, 0xC0, 0xF1];
    assert!(plan.decode(&command.reply, &exception).is_none());
    assert_decoders_agree("fc51/modbus", fast, &slow, &exception);
    let mut corrupt = reply;
    corrupt[8] ^= 1;
    assert!(plan.decode(&command.reply, &corrupt).is_none());
    assert_decoders_agree("fc51/modbus", fast, &slow, &corrupt);
}
