//! When each polled register of a station is due (sans I/O: the caller brings the clock).
//! Registers polled at the same interval form a group read together; a group keeps its
//! rate (its next time is the last one plus the interval) unless it fell a whole interval
//! behind, when it starts again from now instead of catching up in a burst.

use std::time::{Duration, Instant};

/// The registers of one station polled at one interval.
#[derive(Debug, Clone)]
struct Group {
    every: Duration,
    /// Indexes into the station's poll list.
    members: Vec<usize>,
    next: Instant,
}

/// A station's poll schedule.
#[derive(Debug, Clone)]
pub struct Schedule {
    groups: Vec<Group>,
}

impl Schedule {
    /// A schedule for registers polled at `intervals` (one per register, in the poll
    /// list's order), all due at `start`.
    pub fn new(intervals: &[Duration], start: Instant) -> Schedule {
        let mut groups: Vec<Group> = Vec::new();
        for (index, every) in intervals.iter().enumerate() {
            match groups.iter_mut().find(|g| g.every == *every) {
                Some(group) => group.members.push(index),
                None => groups.push(Group {
                    every: *every,
                    members: vec![index],
                    next: start,
                }),
            }
        }
        Schedule { groups }
    }

    /// The registers due at `now` (indexes into the poll list, in its order), and their
    /// groups marked as read: each group's next time moves one interval on.
    pub fn take_due(&mut self, now: Instant) -> Vec<usize> {
        let mut due = Vec::new();
        for group in self.groups.iter_mut().filter(|g| g.next <= now) {
            due.extend_from_slice(&group.members);
            group.next += group.every;
            if group.next <= now {
                group.next = now + group.every;
            }
        }
        due.sort_unstable();
        due
    }

    /// When the next group is due (`None`: nothing is polled).
    pub fn next_due(&self) -> Option<Instant> {
        self.groups.iter().map(|g| g.next).min()
    }

    /// Makes everything due at `now` (a station back online, a register just written).
    pub fn all_due(&mut self, now: Instant) {
        for group in &mut self.groups {
            group.next = now;
        }
    }

    /// Makes the group of register `index` due at `now` (read back after a write).
    pub fn due_now(&mut self, index: usize, now: Instant) {
        for group in &mut self.groups {
            if group.members.contains(&index) {
                group.next = group.next.min(now);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: Duration = Duration::from_secs(1);

    #[test]
    fn registers_of_one_interval_are_read_together_and_keep_their_rate() {
        let t = Instant::now();
        let mut schedule = Schedule::new(&[S, 10 * S, S], t);
        assert_eq!(schedule.take_due(t), [0, 1, 2]);
        assert_eq!(schedule.take_due(t), Vec::<usize>::new());
        assert_eq!(schedule.next_due(), Some(t + S));
        // Read 200 ms late: the next is still on the one-second grid.
        assert_eq!(schedule.take_due(t + S + S / 5), [0, 2]);
        assert_eq!(schedule.next_due(), Some(t + 2 * S));
        assert_eq!(schedule.take_due(t + 10 * S), [0, 1, 2]);
    }

    #[test]
    fn a_group_a_whole_interval_behind_starts_again_without_a_burst() {
        let t = Instant::now();
        let mut schedule = Schedule::new(&[S], t);
        schedule.take_due(t);
        let late = t + 5 * S + S / 2;
        assert_eq!(schedule.take_due(late), [0]);
        assert_eq!(schedule.next_due(), Some(late + S));
        assert!(schedule.take_due(late + S / 2).is_empty());
    }

    #[test]
    fn a_written_register_is_due_at_once() {
        let t = Instant::now();
        let mut schedule = Schedule::new(&[S, 10 * S], t);
        schedule.take_due(t);
        schedule.due_now(1, t + S / 2);
        assert_eq!(schedule.take_due(t + S / 2), [1]);
        schedule.all_due(t + S / 2);
        assert_eq!(schedule.take_due(t + S / 2), [0, 1]);
    }

    #[test]
    fn nothing_polled_is_never_due() {
        let schedule = Schedule::new(&[], Instant::now());
        assert_eq!(schedule.next_due(), None);
    }
}
