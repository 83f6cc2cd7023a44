//! How a protocol shows in `Debug`: every field but its [`super::VariantCache`], so that a
//! protocol shows the same whatever variants it has built.

use super::Protocol;
use std::fmt;

impl fmt::Debug for Protocol {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // Named one by one: a field added to `Protocol` fails here until it is shown.
        let Protocol {
            id,
            name,
            commands,
            error_reply,
            lowercase_means_tripped,
            max_frame_len,
            address_range,
            default_optional_parts,
            error_codes,
            pre_steps,
            default_process,
            frame_gap_chars,
            max_words_per_read,
            max_words_per_write,
            partial_blocks,
            block,
            timing,
            broadcast,
            wire_numbers,
            paging,
            persistence,
            variants,
            unsupported_function,
            variant_cache: _,
        } = self;
        f.debug_struct("Protocol")
            .field("id", id)
            .field("name", name)
            .field("commands", commands)
            .field("error_reply", error_reply)
            .field("lowercase_means_tripped", lowercase_means_tripped)
            .field("max_frame_len", max_frame_len)
            .field("address_range", address_range)
            .field("default_optional_parts", default_optional_parts)
            .field("error_codes", error_codes)
            .field("pre_steps", pre_steps)
            .field("default_process", default_process)
            .field("frame_gap_chars", frame_gap_chars)
            .field("max_words_per_read", max_words_per_read)
            .field("max_words_per_write", max_words_per_write)
            .field("partial_blocks", partial_blocks)
            .field("block", block)
            .field("timing", timing)
            .field("broadcast", broadcast)
            .field("wire_numbers", wire_numbers)
            .field("paging", paging)
            .field("persistence", persistence)
            .field("variants", variants)
            .field("unsupported_function", unsupported_function)
            .finish()
    }
}
