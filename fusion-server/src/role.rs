//! Which of a site's servers publishes: the rules of the election, apart from Zenoh.
//!
//! The active server holds a liveliness token `fusion/<site>/server/active/<instance>`; every
//! server of role `auto` watches those tokens. A standby takes over as soon as no token is
//! held; an active server that sees another active one (both started at once, or a network
//! partition healed) stays active only if its instance id is the smaller, so a split brain
//! ends without any exchange beyond the tokens. A server that returns after a takeover sees
//! the new active's token and stays a standby, whatever its id: the active never changes
//! without a reason. `role = "active"` never stands down.

use std::collections::BTreeSet;

use protocol::{InstanceId, ServerRole};

use crate::config::RoleMode;

/// One server's view of the election: who else holds the active token, and its own role.
#[derive(Debug, Clone)]
pub struct Election {
    me: InstanceId,
    mode: RoleMode,
    others: BTreeSet<InstanceId>,
    role: ServerRole,
}

impl Election {
    /// Before anything is known: standby for `auto`, which first looks for an active server.
    pub fn new(me: InstanceId, mode: RoleMode) -> Self {
        let role = match mode {
            RoleMode::Active => ServerRole::Active,
            RoleMode::Auto => ServerRole::Standby,
        };
        Self {
            me,
            mode,
            others: BTreeSet::new(),
            role,
        }
    }

    /// This server's instance id.
    pub fn me(&self) -> &InstanceId {
        &self.me
    }

    /// This server's current role.
    pub fn role(&self) -> ServerRole {
        self.role
    }

    /// The other servers holding the active token now.
    pub fn other_actives(&self) -> impl Iterator<Item = &InstanceId> {
        self.others.iter()
    }

    /// Another server's token appeared (its own is ignored); returns the role afterwards.
    pub fn token_appeared(&mut self, who: InstanceId) -> ServerRole {
        if who != self.me {
            self.others.insert(who);
        }
        self.decide()
    }

    /// Another server's token went away; returns the role afterwards.
    pub fn token_vanished(&mut self, who: &InstanceId) -> ServerRole {
        self.others.remove(who);
        self.decide()
    }

    /// Applies the rules of the module's header to what is known now.
    pub fn decide(&mut self) -> ServerRole {
        self.role = match (self.mode, self.role) {
            (RoleMode::Active, _) => ServerRole::Active,
            (RoleMode::Auto, ServerRole::Standby) if self.others.is_empty() => ServerRole::Active,
            (RoleMode::Auto, ServerRole::Standby) => ServerRole::Standby,
            (RoleMode::Auto, ServerRole::Active) => {
                if self.others.iter().any(|other| *other < self.me) {
                    ServerRole::Standby
                } else {
                    ServerRole::Active
                }
            }
        };
        self.role
    }

    /// Whether another server holds the token while this one is active and will not yield to
    /// it (two `role = "active"` servers, or an `auto` one facing them): worth a warning.
    pub fn split_brain(&self) -> bool {
        self.role == ServerRole::Active && !self.others.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn id(s: &str) -> InstanceId {
        InstanceId::new(s).unwrap()
    }

    #[test]
    fn a_lone_auto_server_becomes_active_and_a_second_one_stands_by() {
        let mut a = Election::new(id("a"), RoleMode::Auto);
        assert_eq!(a.decide(), ServerRole::Active);
        let mut b = Election::new(id("b"), RoleMode::Auto);
        assert_eq!(b.token_appeared(id("a")), ServerRole::Standby);
        assert_eq!(b.decide(), ServerRole::Standby);
        // The active one goes away: the standby takes over.
        assert_eq!(b.token_vanished(&id("a")), ServerRole::Active);
    }

    #[test]
    fn a_returning_server_stays_standby_whatever_its_id() {
        let mut a = Election::new(id("a"), RoleMode::Auto);
        assert_eq!(a.token_appeared(id("b")), ServerRole::Standby);
    }

    #[test]
    fn a_split_brain_keeps_the_smaller_id_active() {
        let mut a = Election::new(id("a"), RoleMode::Auto);
        let mut b = Election::new(id("b"), RoleMode::Auto);
        assert_eq!(a.decide(), ServerRole::Active);
        assert_eq!(b.decide(), ServerRole::Active);
        assert_eq!(a.token_appeared(id("b")), ServerRole::Active);
        assert!(a.split_brain());
        assert_eq!(b.token_appeared(id("a")), ServerRole::Standby);
        assert_eq!(a.token_vanished(&id("b")), ServerRole::Active);
        assert!(!a.split_brain());
    }

    #[test]
    fn an_active_mode_server_never_stands_down_and_its_own_token_is_ignored() {
        let mut main = Election::new(id("main"), RoleMode::Active);
        assert_eq!(main.token_appeared(id("main")), ServerRole::Active);
        assert_eq!(main.other_actives().count(), 0);
        assert_eq!(main.token_appeared(id("a")), ServerRole::Active);
        assert!(main.split_brain());
    }

    proptest! {
        /// Whatever the order in which any number of auto servers start and see each other's
        /// tokens, once every token is known exactly one is active: the smallest id.
        #[test]
        fn every_split_brain_settles_on_one_active_server(
            n in 2usize..6,
            order in proptest::collection::vec((0usize..6, 0usize..6), 0..40),
        ) {
            let ids: Vec<InstanceId> = (0..n).map(|i| id(&format!("s{i}"))).collect();
            let mut servers: Vec<Election> =
                ids.iter().map(|me| Election::new(me.clone(), RoleMode::Auto)).collect();
            // Everyone starts alone (no token seen yet): all active.
            for server in &mut servers {
                server.decide();
            }
            // Tokens are seen in an arbitrary order, a token counted only while its holder is
            // active; finally every server sees every token still held.
            let step = |servers: &mut Vec<Election>, watcher: usize, holder: usize| {
                if servers[holder].role() == ServerRole::Active {
                    servers[watcher].token_appeared(ids[holder].clone());
                } else {
                    servers[watcher].token_vanished(&ids[holder]);
                }
            };
            for (watcher, holder) in order {
                step(&mut servers, watcher % n, holder % n);
            }
            for _ in 0..n {
                for watcher in 0..n {
                    for holder in 0..n {
                        step(&mut servers, watcher, holder);
                    }
                }
            }
            let active: Vec<usize> =
                (0..n).filter(|&i| servers[i].role() == ServerRole::Active).collect();
            prop_assert_eq!(active, vec![0]);
        }
    }
}
