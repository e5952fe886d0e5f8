#!/usr/bin/env python3
"""Renders docker/deployment.txt (one line per sensor, server and client) for docker/make-certs.sh.

  render-deployment.py identities FILE   one line per identity: <common name> <user> <file stem>
  render-deployment.py acl FILE          the router's `access_control` section (JSON, valid JSON5)

The access control (Zenoh 1.10, default deny) follows the keys of protocol/src/keys.rs:
- an edge agent may put, hold liveliness tokens, declare queryables and reply only under its own
  fusion/<site>/sensors/<sensor>/** (and put fusion/<site>/truth when marked `truth`);
- a site's servers may put fusion/<site>/tracks, fusion/<site>/tracks/json and under
  fusion/<site>/server/**, answer fusion/<site>/tracks, fusion/<site>/status and fusion/<site>/server/**,
  hold liveliness tokens under fusion/<site>/server/**, and read (subscribe, query, liveliness) their
  site's sensors/**, server/** and tracks;
- a client may only read: subscribe, query, liveliness-subscribe and liveliness-query fusion/**.
Egress rules say what the router may forward to each identity: data, replies and tokens where the
identity reads, and the subscriber declarations and queries of others (a publisher learns who
listens; a queryable receives the queries meant for it). Every subject is a certificate common name
AND the user name of its role (user/password is the second factor). Python 3 standard library only.
"""

import json
import re
import sys

CHUNK = re.compile(r"^[A-Za-z0-9_-]{1,64}$")
ALL_READS = ["declare_subscriber", "query", "declare_liveliness_subscriber", "liveliness_query"]
RECEIVED = ["put", "reply", "liveliness_token"]
ROUTED_TO_WRITERS = ["declare_subscriber", "query"]


def parse(path):
    """The deployment as {"sites": [{"name", "sensors": [(name, truth)], "servers": [id]}], "clients": [..]}."""
    sites, clients = [], []
    for number, raw in enumerate(open(path, encoding="utf-8"), 1):
        words = raw.split("#", 1)[0].split()
        if not words:
            continue
        kind, args = words[0], words[1:]

        def fail(why):
            sys.exit(f"{path}:{number}: {why}: {raw.strip()}")

        if not args or not all(CHUNK.match(a) for a in args[:1]):
            fail("expected a name of 1 to 64 characters of [A-Za-z0-9_-]")
        if kind == "site":
            sites.append({"name": args[0], "sensors": [], "servers": []})
        elif kind == "client":
            clients.append(args[0])
        elif kind in ("sensor", "server"):
            if not sites:
                fail(f"a `{kind}` line before any `site` line")
            if kind == "sensor":
                if args[1:] not in ([], ["truth"]):
                    fail("a sensor takes one optional word, `truth`")
                sites[-1]["sensors"].append((args[0], args[1:] == ["truth"]))
            else:
                sites[-1]["servers"].append(args[0])
        else:
            fail(f"unknown line kind `{kind}`")
    return {"sites": sites, "clients": clients}


def identities(deployment):
    """(common name, user name, file stem) of every identity."""
    out = []
    for site in deployment["sites"]:
        s = site["name"]
        out += [(f"{s}/{name}", "edge-agent", f"agent-{s}-{name}") for name, _ in site["sensors"]]
        out += [(f"{s}/server/{i}", "server", f"server-{s}-{i}") for i in site["servers"]]
    out += [(name, name, f"client-{name}") for name in deployment["clients"]]
    return out


def rule(rule_id, flows, messages, keys):
    return {"id": rule_id, "permission": "allow", "flows": flows, "messages": messages, "key_exprs": keys}


def acl(deployment):
    rules, subjects, policies = [], [], []

    def grant(subject_id, common_names, user, own_rules):
        subjects.append({"id": subject_id, "cert_common_names": common_names, "usernames": [user]})
        for r in own_rules:
            if r["id"] not in {x["id"] for x in rules}:
                rules.append(r)
        policies.append({"id": subject_id, "subjects": [subject_id], "rules": [r["id"] for r in own_rules]})

    writers_egress = rule("routed to writers", ["egress"], ROUTED_TO_WRITERS, ["fusion/**"])
    for site in deployment["sites"]:
        s = site["name"]
        root = f"fusion/{s}"
        for name, truth in site["sensors"]:
            own = f"{root}/sensors/{name}/**"
            publish = rule(f"agent {s}/{name} publishes", ["ingress"],
                           ["put", "liveliness_token", "declare_queryable", "reply"], [own])
            extra = [rule(f"agent {s}/{name} publishes the truth", ["ingress"], ["put"], [f"{root}/truth"])] if truth else []
            grant(f"agent {s}/{name}", [f"{s}/{name}"], "edge-agent", [publish, *extra, writers_egress])
        if site["servers"]:
            outputs = [f"{root}/tracks", f"{root}/tracks/json", f"{root}/server/**"]
            answered = [f"{root}/tracks", f"{root}/status", f"{root}/server/**"]
            read = [f"{root}/sensors/**", f"{root}/server/**", f"{root}/tracks/**"]
            grant(f"servers {s}", [f"{s}/server/{i}" for i in site["servers"]], "server", [
                rule(f"servers {s} publish", ["ingress"], ["put"], outputs),
                rule(f"servers {s} answer", ["ingress"], ["declare_queryable", "reply"], answered),
                rule(f"servers {s} hold tokens", ["ingress"], ["liveliness_token"], [f"{root}/server/**"]),
                rule(f"servers {s} read", ["ingress"], ALL_READS, read),
                rule(f"servers {s} receive", ["egress"], RECEIVED, read),
                writers_egress,
            ])
    reads = rule("clients read", ["ingress"], ALL_READS, ["fusion/**"])
    receive = rule("clients receive", ["egress"], RECEIVED, ["fusion/**"])
    for name in deployment["clients"]:
        grant(f"client {name}", [name], name, [reads, receive])
    return {"enabled": True, "default_permission": "deny", "rules": rules, "subjects": subjects, "policies": policies}


def render(section):
    """JSON with one rule, subject or policy per line (diffable, still valid JSON5)."""
    lines = ["{"]
    for key in ("enabled", "default_permission"):
        lines.append(f"  {json.dumps(key)}: {json.dumps(section[key])},")
    for key in ("rules", "subjects", "policies"):
        lines.append(f"  {json.dumps(key)}: [")
        lines += [f"    {json.dumps(item)}," for item in section[key]]
        lines.append("  ],")
    return "\n".join(lines) + "\n}"


def main():
    if len(sys.argv) != 3 or sys.argv[1] not in ("identities", "acl"):
        sys.exit(__doc__)
    deployment = parse(sys.argv[2])
    if sys.argv[1] == "identities":
        for cn, user, stem in identities(deployment):
            print(cn, user, stem)
    else:
        print(render(acl(deployment)))


if __name__ == "__main__":
    main()
