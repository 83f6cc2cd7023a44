//! The MQTT client as one of the service's outputs: every event published (never waiting
//! for the broker), and at the end every station and the service reported offline.

use super::mqtt::Mqtt;
use super::output::Output;
use vfd_bus::service::event::Event;

/// [`Mqtt`] as an [`Output`].
pub struct MqttOutput(pub Mqtt);

impl Output for MqttOutput {
    fn event(&mut self, event: &Event) -> Result<(), String> {
        self.0.publish(event);
        Ok(())
    }

    fn finish(self: Box<Self>) {
        self.0.shutdown();
    }
}
