//! A protocol with no plan in any layout, for comparing the planned and interpreted paths.

use super::command::CommandSpec;
use super::follow_up::FollowUp;
use super::Protocol;
use crate::layout::FrameLayout;
use std::borrow::Cow;

impl Protocol {
    /// This protocol with no plan in any layout: every frame goes through the interpreter,
    /// as for a layout no plan covers. For comparing the two paths (the differential tests,
    /// the `plan_agreement` fuzz target, the codec benchmark); a master or tool has no
    /// reason to use it.
    pub fn without_plans(&self) -> Protocol {
        let commands = self
            .commands
            .iter()
            .map(|command| CommandSpec {
                request: command.request.clone().unplanned(),
                reply: command.reply.clone().unplanned(),
                follow_up: command.follow_up.as_ref().map(|f| FollowUp {
                    ok: f.ok.clone().unplanned(),
                    again: f.again.clone().unplanned(),
                }),
                ..command.clone()
            })
            .collect();
        Protocol {
            commands: Cow::Owned(commands),
            error_reply: self.error_reply.clone().map(FrameLayout::unplanned),
            ..self.clone()
        }
    }
}
