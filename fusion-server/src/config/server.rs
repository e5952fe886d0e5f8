//! `[server]`: this server's part at its site — alone, or one of an active server and hot
//! standbys (`role.rs` says how they agree on which one publishes).

use protocol::InstanceId;
use serde::Deserialize;

use super::{invalid, positive, ConfigError};

/// How a server decides whether it publishes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RoleMode {
    /// Always publishes: the site's only server.
    #[default]
    Active,
    /// Publishes while no other server of the site does, stands by otherwise; two or more such
    /// servers make a site highly available.
    Auto,
}

/// `[server]`: the server's role and its name among the site's servers.
#[derive(Debug, Clone, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ServerRoleConfig {
    /// `active` (the default: a lone server) or `auto` (active or hot standby).
    pub role: RoleMode,
    /// This server's name among the site's servers (one key chunk, e.g. `a`); required with
    /// `role = "auto"`, where each server needs its own. When two servers are active at once,
    /// the one with the smaller id stays active.
    pub instance_id: Option<String>,
    /// Seconds between two times a standby takes the active server's filter state (and once when
    /// it starts or stands down), so that whatever the two saw differently (a set one of them
    /// missed, a late set handled at another moment) cannot part their labels for longer.
    pub standby_sync_s: f64,
}

impl Default for ServerRoleConfig {
    fn default() -> Self {
        Self {
            role: RoleMode::Active,
            instance_id: None,
            standby_sync_s: 2.0,
        }
    }
}

/// The instance id of a lone server that names none.
const DEFAULT_INSTANCE: &str = "main";

impl ServerRoleConfig {
    /// This server's instance id (`main` when a lone active server names none).
    pub fn instance(&self) -> InstanceId {
        let id = self.instance_id.as_deref().unwrap_or(DEFAULT_INSTANCE);
        InstanceId::new(id).unwrap_or_else(|_| unreachable!("validated at load"))
    }

    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        positive("server.standby_sync_s", self.standby_sync_s)?;
        match &self.instance_id {
            Some(id) => InstanceId::new(id.as_str())
                .map(|_| ())
                .map_err(|e| invalid("server.instance_id", e.to_string())),
            None if self.role == RoleMode::Auto => Err(invalid(
                "server.instance_id",
                "required with role = \"auto\": every server of a site needs its own",
            )),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_needs_an_instance_id_and_ids_must_be_key_chunks() {
        let auto = ServerRoleConfig {
            role: RoleMode::Auto,
            ..ServerRoleConfig::default()
        };
        assert!(auto
            .validate()
            .unwrap_err()
            .to_string()
            .contains("server.instance_id"));
        let bad = ServerRoleConfig {
            role: RoleMode::Auto,
            instance_id: Some("a/b".into()),
            ..ServerRoleConfig::default()
        };
        assert!(bad.validate().is_err());
        let lone = ServerRoleConfig::default();
        lone.validate().unwrap();
        assert_eq!(lone.instance().as_str(), "main");
    }
}
