#!/usr/bin/env python3
"""Structure checks of deploy/: the Kubernetes manifests (kustomize base and overlay), the
docker-compose file and the Prometheus files agree with each other and with the real server.

  check_deploy.py manifests --source ROOT --server BIN   the files as written, and the server's
                                                         own check of every setting and flag
  check_deploy.py render --source ROOT                   `kubectl kustomize` of base and overlay;
                                                         exit 77 (skipped) without kubectl

Every server setting and flag the files name is checked by the real `ricochet-server
--print-config` (it loads, validates, prints the effective configuration and exits 0, or 2 with
the reason); the effective configuration it prints is what the ports are compared with.
Each problem is printed; the exit code is 1 when there is any.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import yaml

SKIPPED = 77  # ctest SKIP_RETURN_CODE

# The Agones health ping of the server (issue 31 §3: `POST /health` every 2 s while every match
# ticks on time), in seconds.
HEALTH_PING_S = 2
# A hung server is replaced within this long once its health checks began (periodSeconds times
# failureThreshold), in seconds.
MAX_UNHEALTHY_DETECTION_S = 30
# The server's backstop after its shutdown grace (server/src/main.cpp), in seconds.
SHUTDOWN_BACKSTOP_S = 2

# Where the image installs what the server reads (Dockerfile).
IMAGE_MAPS_DIR = "/usr/local/share/ricochet/maps/"

# Where the server names the Fleet's two ports it advertises under Agones.
AGONES_PORT_NAMES_HEADER = "server/src/net/agones_game_server.h"


def agones_port_names(source):
    """The names the server reads GET /gameserver's status.ports by: {"control": .., "game": ..}."""
    header = (source / AGONES_PORT_NAMES_HEADER).read_text(encoding="utf-8")
    found = re.findall(r'kAgones(Control|Game)PortName\s*=\s*"([^"]+)"', header)
    return {kind.lower(): name for kind, name in found}


def outbox_path(config):
    """db.outbox_dir as the server resolves it (a relative one is under server.data_dir)."""
    outbox = config["db"]["outbox_dir"]
    if outbox.startswith("/"):
        return outbox
    return config["server"]["data_dir"].rstrip("/") + "/" + outbox


class Problems:
    def __init__(self):
        self.items = []

    def check(self, condition, text):
        if not condition:
            self.items.append(text)
        return condition


def load_yaml_documents(path):
    with open(path, encoding="utf-8") as file:
        return [doc for doc in yaml.safe_load_all(file) if doc is not None]


def load_yaml(path):
    documents = load_yaml_documents(path)
    if len(documents) != 1:
        raise ValueError(f"{path}: expected one YAML document, found {len(documents)}")
    return documents[0]


class Server:
    """The real ricochet-server: its flags (--help) and its check of a configuration."""

    def __init__(self, binary):
        self.binary = binary
        help_text = subprocess.run([binary, "--help"], capture_output=True, text=True,
                                   timeout=30, check=True).stdout
        self.flags = set(re.findall(r"(--[a-z][a-z0-9-]*)", help_text))

    def effective_config(self, args, problems, where):
        """The configuration `args` give, as the server prints it; None when it refuses them."""
        kept = []
        for arg in args:
            flag = arg.split("=", 1)[0]
            if flag.startswith("--"):
                problems.check(flag in self.flags, f"{where}: ricochet-server has no flag {flag}")
            kept.append(arg)
        run = subprocess.run([self.binary, *kept, "--print-config"], capture_output=True,
                             text=True, timeout=30)
        if not problems.check(run.returncode == 0,
                              f"{where}: ricochet-server {' '.join(kept)} --print-config exited "
                              f"{run.returncode}:\n{run.stderr}{run.stdout}"):
            return None
        return tomllib.loads(run.stdout)


def config_keys(toml):
    return {(section, key) for section, table in toml.items() for key in table}


def check_config_file(path, server, problems):
    """Every key of the file is one the server has (it also refuses unknown keys itself)."""
    with open(path, "rb") as file:
        toml = tomllib.load(file)
    defaults = server.effective_config([], problems, "defaults")
    for section, key in sorted(config_keys(toml) - config_keys(defaults or {})):
        problems.check(False, f"{path}: [{section}] {key} is no server setting")
    return toml


def expand_env(arg, env_values, problems, where):
    """$(NAME) as kubelet expands it from the container's env: each must be defined."""
    def value(match):
        name = match.group(1)
        problems.check(name in env_values, f"{where}: {arg} names $({name}), not in env")
        return env_values.get(name, "")
    return re.sub(r"\$\(([A-Za-z_][A-Za-z0-9_]*)\)", value, arg)


def flag_value(args, flag):
    for index, arg in enumerate(args):
        if arg == flag and index + 1 < len(args):
            return args[index + 1]
        if arg.startswith(flag + "="):
            return arg.split("=", 1)[1]
    return None


def replace_config_path(args, local_path):
    out = []
    skip = False
    for arg in args:
        if skip:
            skip = False
            continue
        if arg == "--config":
            skip = True
            continue
        if arg.startswith("--config="):
            continue
        out.append(arg)
    return ["--config", str(local_path), *out]


def check_maps(config, source, problems, where):
    dockerfile = (source / "Dockerfile").read_text(encoding="utf-8")
    for map_path in config["matches"]["maps"]:
        if not problems.check(map_path.startswith(IMAGE_MAPS_DIR),
                              f"{where}: map {map_path} is not under the image's {IMAGE_MAPS_DIR}"):
            continue
        name = map_path[len(IMAGE_MAPS_DIR):]
        problems.check((source / "server/maps" / name).is_file(),
                       f"{where}: map {map_path}: no server/maps/{name}")
        problems.check(f"server/maps/{name}" in dockerfile,
                       f"{where}: map {map_path}: the Dockerfile does not install "
                       f"server/maps/{name}")


def check_tick_budget_alert(source, config, problems):
    rules = load_yaml(source / "deploy/prometheus/alerts.yml")
    exprs = {rule["alert"]: rule["expr"] for group in rules["groups"] for rule in group["rules"]
             if "alert" in rule}
    expr = exprs.get("RicochetTickP99OverBudget", "")
    match = re.search(r">\s*1\s*/\s*(\d+)", expr)
    rate = config["game"]["tick_rate_hz"]
    problems.check(match is not None and int(match.group(1)) == rate,
                   f"alerts.yml RicochetTickP99OverBudget: the budget must be 1 / {rate} "
                   f"(game.tick_rate_hz of the deployed config), got: {expr!r}")


# ----------------------------------------------------------------------------------- kustomize

class Kustomization:
    def __init__(self, directory):
        self.directory = Path(directory)
        self.spec = load_yaml(self.directory / "kustomization.yaml")
        self.resources = []  # (file, document) of this directory's own resource files
        self.bases = []
        for entry in self.spec.get("resources", []):
            path = self.directory / entry
            if path.is_dir():
                self.bases.append(Kustomization(path))
            else:
                for document in load_yaml_documents(path):
                    self.resources.append((path, document))

    def of_kind(self, kind):
        return [doc for _, doc in self.resources if doc.get("kind") == kind]

    def generator(self, kind, name):
        key = "configMapGenerator" if kind == "ConfigMap" else "secretGenerator"
        for entry in self.spec.get(key, []):
            if entry["name"] == name:
                return entry
        return None

    def env_value(self, env):
        """A container env entry's value: given, or a literal of a generated Secret or
        ConfigMap; empty when it is neither."""
        if "value" in env:
            return env["value"]
        source = env.get("valueFrom", {})
        for kind, ref_key in (("Secret", "secretKeyRef"), ("ConfigMap", "configMapKeyRef")):
            ref = source.get(ref_key)
            entry = self.generator(kind, ref["name"]) if ref else None
            for literal in (entry or {}).get("literals", []):
                key, _, value = literal.partition("=")
                if key == ref["key"]:
                    return value
        return ""

    def generated_keys(self, kind, name, problems):
        """The keys (file names) a generator makes, or None when no generator has `name`."""
        entry = self.generator(kind, name)
        if entry is None:
            return None
        keys = set()
        for literal in entry.get("literals", []):
            keys.add(literal.split("=", 1)[0])
        for file_entry in entry.get("files", []):
            key, _, path = file_entry.rpartition("=")
            path = path or file_entry
            problems.check((self.directory / path).is_file(),
                           f"{self.directory}: {kind} {name}: no file {path}")
            keys.add(key or Path(path).name)
        for env_file in entry.get("envs", []):
            env_path = self.directory / env_file
            if problems.check(env_path.is_file(), f"{self.directory}: no env file {env_file}"):
                for line in env_path.read_text(encoding="utf-8").splitlines():
                    if line.strip() and not line.startswith("#"):
                        keys.add(line.split("=", 1)[0])
        return keys


def only(items, what, problems):
    if problems.check(len(items) == 1, f"expected exactly one {what}, found {len(items)}"):
        return items[0]
    return None


def check_fleet(base, source, server, problems):
    fleet = only(base.of_kind("Fleet"), "Fleet in the base", problems)
    if fleet is None:
        return None
    gameserver = fleet["spec"]["template"]
    pod = gameserver["spec"]["template"]
    containers = pod["spec"]["containers"]
    container = only(containers, "container in the GameServer pod", problems)
    if container is None:
        return None
    where = "fleet.yaml"

    # The configuration: --config is the ConfigMap's file, mounted.
    mounts = {mount["name"]: mount for mount in container.get("volumeMounts", [])}
    volumes = {volume["name"]: volume for volume in pod["spec"].get("volumes", [])}
    for name in mounts:
        problems.check(name in volumes, f"{where}: volumeMount {name} has no volume")
    args = [*container.get("command", []), *container.get("args", [])]
    problems.check(args[:1] == ["ricochet-server"], f"{where}: the container must run "
                   f"ricochet-server, runs {args[:1]}")
    args = args[1:]
    env_values = {env["name"]: base.env_value(env) for env in container.get("env", [])}
    args = [expand_env(arg, env_values, problems, where) for arg in args]
    config_path = flag_value(args, "--config")
    config_file = None
    for name, mount in mounts.items():
        volume = volumes.get(name, {})
        if config_path and "configMap" in volume and \
                config_path.startswith(mount["mountPath"].rstrip("/") + "/"):
            key = config_path[len(mount["mountPath"].rstrip("/")) + 1:]
            config_map = volume["configMap"]["name"]
            keys = base.generated_keys("ConfigMap", config_map, problems)
            if problems.check(keys is not None and key in keys,
                              f"{where}: --config {config_path}: ConfigMap {config_map} has no "
                              f"key {key}"):
                config_file = base.directory / key
    if not problems.check(config_file is not None,
                          f"{where}: --config {config_path} is no file of a mounted ConfigMap"):
        return None
    check_config_file(config_file, server, problems)
    config = server.effective_config(replace_config_path(args, config_file), problems, where)
    if config is None:
        return None

    # Ports: the GameServer's ports are the server's, with the right protocols, named as the
    # server reads them from GET /gameserver (it advertises their host ports).
    ports = {port["name"]: port for port in gameserver["spec"].get("ports", [])}
    defaults = server.effective_config([], problems, "defaults") or config
    names = agones_port_names(source)
    problems.check(set(names) == {"control", "game"},
                   f"{AGONES_PORT_NAMES_HEADER}: no kAgonesControlPortName and "
                   f"kAgonesGamePortName, found {names}")
    for name, section, protocol in ((names.get("control"), "control", "TCP"),
                                    (names.get("game"), "game", "UDP")):
        port = ports.get(name)
        if not problems.check(port is not None, f"{where}: no GameServer port named {name}"):
            continue
        problems.check(port.get("protocol") == protocol,
                       f"{where}: port {name} must be {protocol}, is {port.get('protocol')}")
        problems.check(port.get("portPolicy") in ("Dynamic", "Passthrough", "Static", "None"),
                       f"{where}: port {name}: portPolicy {port.get('portPolicy')!r}")
        problems.check(port.get("containerPort") == config[section]["port"],
                       f"{where}: port {name}: containerPort {port.get('containerPort')} but the "
                       f"server listens on {section}.port {config[section]['port']}")
        problems.check(port.get("containerPort") == defaults[section]["port"],
                       f"{where}: port {name}: containerPort {port.get('containerPort')}, not the "
                       f"server's default {section}.port {defaults[section]['port']}")
        problems.check(config[section]["bind"] == "0.0.0.0",
                       f"{where}: {section}.bind must be 0.0.0.0 in a pod, is "
                       f"{config[section]['bind']}")
    problems.check(len(ports) == 2, f"{where}: GameServer ports {sorted(ports)}: only control "
                   "and game reach players")

    # Placement: on, and advertising what Agones says (the host ports of Dynamic port policy
    # differ per GameServer, so no fixed value can be right).
    placement = config["placement"]
    problems.check(placement["enabled"] != "off",
                   f"{where}: placement.enabled is off: the fleet's servers answer no find_match")
    problems.check(placement["advertise_host"] == "" and
                   placement["advertise_control_port"] == 0 and
                   placement["advertise_game_port"] == 0,
                   f"{where}: [placement] advertise_host, advertise_control_port and "
                   "advertise_game_port must be unset under Agones (the GameServer's "
                   f"status.address and port host ports are advertised then), got {placement}")

    # Health: the server pings every HEALTH_PING_S.
    health = gameserver["spec"].get("health", {})
    period = health.get("periodSeconds", 5)
    threshold = health.get("failureThreshold", 3)
    delay = health.get("initialDelaySeconds", 5)
    problems.check(not health.get("disabled", False), f"{where}: health checks are disabled")
    problems.check(period >= 2 * HEALTH_PING_S,
                   f"{where}: health.periodSeconds {period} must hold two {HEALTH_PING_S} s "
                   f"pings (>= {2 * HEALTH_PING_S}), or one late ping fails a period")
    problems.check(threshold >= 2, f"{where}: health.failureThreshold {threshold}: one missed "
                   "period must not kill a GameServer")
    problems.check(period * threshold <= MAX_UNHEALTHY_DETECTION_S,
                   f"{where}: health.periodSeconds x failureThreshold = {period * threshold} s, "
                   f"more than {MAX_UNHEALTHY_DETECTION_S} s to replace a hung server")
    problems.check(delay >= HEALTH_PING_S, f"{where}: health.initialDelaySeconds {delay} is "
                   f"shorter than one ping ({HEALTH_PING_S} s)")

    # Shutdown: Kubernetes waits for the server's grace and backstop.
    grace = pod["spec"].get("terminationGracePeriodSeconds", 30)
    problems.check(grace > config["server"]["shutdown_grace_s"] + SHUTDOWN_BACKSTOP_S,
                   f"{where}: terminationGracePeriodSeconds {grace} must exceed "
                   f"server.shutdown_grace_s {config['server']['shutdown_grace_s']} + "
                   f"{SHUTDOWN_BACKSTOP_S}")

    # Resources: match threads fit the CPU request; memory is bounded.
    resources = container.get("resources", {})
    cpu = str(resources.get("requests", {}).get("cpu", "0"))
    cores = int(cpu[:-1]) / 1000 if cpu.endswith("m") else float(cpu)
    threads = config["server"]["threads"]
    problems.check(cores >= 1, f"{where}: CPU request {cpu}: a server needs a whole core")
    problems.check(0 < threads <= max(1, int(cores)),
                   f"{where}: server.threads {threads} must be 1..the CPU request ({cpu}); 0 "
                   "would start one per core of the node")
    problems.check("memory" in resources.get("requests", {}) and
                   "memory" in resources.get("limits", {}),
                   f"{where}: memory request and limit")

    # Files the server writes and reads: its data_dir on a writable volume, its token file in
    # the mounted Secret.
    def mounted(path, kind):
        for name, mount in mounts.items():
            prefix = mount["mountPath"].rstrip("/")
            if (path == prefix or path.startswith(prefix + "/")) and kind in volumes.get(name, {}):
                return name, mount, volumes[name], path[len(prefix) + 1:]
        return None

    problems.check(mounted(config["server"]["data_dir"], "emptyDir") is not None,
                   f"{where}: server.data_dir {config['server']['data_dir']} is on no emptyDir "
                   "volume (the root filesystem is read-only)")
    # The results outbox outlives the pod: on the Fleet's shared claim, not an emptyDir.
    outbox = mounted(outbox_path(config), "persistentVolumeClaim")
    if problems.check(outbox is not None,
                      f"{where}: db.outbox_dir {outbox_path(config)} is on no "
                      "persistentVolumeClaim: on the pod's emptyDir the results waiting for the "
                      "database are lost with the pod"):
        claim = outbox[2]["persistentVolumeClaim"]["claimName"]
        claims = {doc["metadata"]["name"]: doc for doc in base.of_kind("PersistentVolumeClaim")}
        problems.check(claim in claims and
                       "ReadWriteMany" in claims[claim]["spec"].get("accessModes", []),
                       f"{where}: the outbox's claim {claim} must be a ReadWriteMany "
                       "PersistentVolumeClaim of the base: every GameServer of the Fleet, on "
                       "any node, mounts it")
        problems.check(not outbox[1].get("readOnly", False),
                       f"{where}: the outbox volume is mounted read-only")
    token = mounted(config["admin"]["token_file"], "secret")
    if problems.check(token is not None, f"{where}: admin.token_file "
                      f"{config['admin']['token_file']!r} is no file of a mounted Secret; the "
                      "admin port is not loopback, so /metrics needs it"):
        secret = token[2]["secret"]["secretName"]
        keys = base.generated_keys("Secret", secret, problems)
        problems.check(keys is not None and token[3] in keys,
                       f"{where}: Secret {secret} has no key {token[3]}")
    for env in container.get("env", []):
        ref = env.get("valueFrom", {}).get("secretKeyRef")
        if ref:
            keys = base.generated_keys("Secret", ref["name"], problems)
            problems.check(keys is not None and ref["key"] in keys,
                           f"{where}: env {env['name']}: Secret {ref['name']} has no key "
                           f"{ref['key']}")

    # Labels: the GameServer and its pod carry the labels the PodMonitor selects.
    pod_labels = pod.get("metadata", {}).get("labels", {})
    problems.check(gameserver.get("metadata", {}).get("labels", {}) == pod_labels,
                   f"{where}: the GameServer's labels and its pod's differ")
    admin_ports = {port["name"]: port for port in container.get("ports", [])}
    for monitor in base.of_kind("PodMonitor"):
        selector = monitor["spec"]["selector"].get("matchLabels", {})
        problems.check(selector and all(pod_labels.get(k) == v for k, v in selector.items()),
                       f"podmonitor.yaml: selector {selector} does not select the pods "
                       f"{pod_labels}")
        for endpoint in monitor["spec"]["podMetricsEndpoints"]:
            port = admin_ports.get(endpoint.get("port"))
            if problems.check(port is not None, f"podmonitor.yaml: port {endpoint.get('port')}"
                              " is no container port"):
                problems.check(port["containerPort"] == config["admin"]["port"] and
                               port.get("protocol", "TCP") == "TCP",
                               f"podmonitor.yaml: port {endpoint['port']} is {port}, the admin "
                               f"port is {config['admin']['port']}/TCP")
            problems.check(endpoint.get("path", "/metrics") == "/metrics",
                           "podmonitor.yaml: path must be /metrics")
            credentials = endpoint.get("authorization", {}).get("credentials")
            if problems.check(credentials is not None, "podmonitor.yaml: no bearer token; "
                              "/metrics refuses without it"):
                problems.check(token is not None and
                               credentials["name"] == token[2]["secret"]["secretName"] and
                               credentials["key"] == token[3],
                               f"podmonitor.yaml: credentials {credentials} are not the "
                               "Secret of admin.token_file")
    problems.check(config["admin"]["bind"] == "0.0.0.0",
                   f"{where}: admin.bind must be 0.0.0.0 for Prometheus to reach it")
    check_maps(config, source, problems, where)
    return fleet, config


def check_autoscaler(autoscaler, fleet_name, problems, where):
    """A Buffer FleetAutoscaler Agones accepts, of the Fleet `fleet_name` (None: not checked)."""
    spec = autoscaler["spec"]
    if fleet_name is not None:
        problems.check(spec.get("fleetName") == fleet_name,
                       f"{where}: FleetAutoscaler fleetName {spec.get('fleetName')} is not the "
                       f"Fleet {fleet_name}")
    policy = spec["policy"]
    problems.check(policy["type"] == "Buffer", f"{where}: policy {policy['type']}")
    buffer = policy.get("buffer", {})
    size = buffer.get("bufferSize")
    if isinstance(size, int):
        problems.check(buffer.get("minReplicas", 0) >= size,
                       f"{where}: minReplicas {buffer.get('minReplicas')} below bufferSize "
                       f"{size} (Agones refuses it)")
    problems.check(buffer.get("maxReplicas", 0) >= buffer.get("minReplicas", 0),
                   f"{where}: maxReplicas below minReplicas")


def check_overlay(overlay, base, problems):
    where = str(overlay.directory)
    for entry in overlay.spec.get("secretGenerator", []) + overlay.spec.get("configMapGenerator",
                                                                            []):
        kind = "Secret" if entry in overlay.spec.get("secretGenerator", []) else "ConfigMap"
        if entry.get("behavior") in ("replace", "merge"):
            base_keys = base.generated_keys(kind, entry["name"], problems)
            keys = overlay.generated_keys(kind, entry["name"], problems)
            problems.check(base_keys is not None and keys is not None and
                           (keys == base_keys if entry["behavior"] == "replace" else True),
                           f"{where}: {kind} {entry['name']} keys {keys} do not replace the "
                           f"base's {base_keys}")
    for patch in overlay.spec.get("patches", []):
        document = load_yaml(overlay.directory / patch["path"])
        names = {(doc.get("kind"), doc["metadata"]["name"]) for _, doc in base.resources}
        problems.check((document["kind"], document["metadata"]["name"]) in names,
                       f"{where}: patch {patch['path']} names no resource of the base")
        if document["kind"] == "FleetAutoscaler":
            check_autoscaler(document, None, problems, f"{where}/{patch['path']}")


# ------------------------------------------------------------------------- compose, Prometheus

def check_compose(source, server, problems):
    deploy = source / "deploy"
    compose = load_yaml(deploy / "docker-compose.yml")
    services = compose["services"]
    where = "docker-compose.yml"
    postgres = services.get("postgres", {})
    problems.check(re.search(r"postgres:15(\b|$)", postgres.get("image", "")) is not None,
                   f"{where}: postgres must be PostgreSQL 15, is {postgres.get('image')}")
    servers = {}
    outboxes = set()  # the volumes the servers' outboxes are on
    for name, service in services.items():
        command = service.get("command", [])
        if command[:1] != ["ricochet-server"]:
            continue
        mounts = {}
        for volume in service.get("volumes", []):
            host, _, container = volume.partition(":")
            container = container.split(":")[0]
            if host.startswith("."):
                mounts[container] = (deploy / host).resolve()
        args = command[1:]
        config_path = flag_value(args, "--config")
        local = mounts.get(config_path)
        if not problems.check(local is not None and local.is_file(),
                              f"{where}: {name}: --config {config_path} is no mounted file"):
            continue
        check_config_file(local, server, problems)
        config = server.effective_config(replace_config_path(args, local), problems,
                                         f"{where}: {name}")
        if config is None:
            continue
        servers[name] = config
        published = {}
        for port in service.get("ports", []):
            spec, _, protocol = str(port).partition("/")
            parts = spec.split(":")
            published[(int(parts[-1]), protocol or "tcp")] = (int(parts[-2]), parts[:-2])
        for section, protocol in (("control", "tcp"), ("game", "udp")):
            port = config[section]["port"]
            mapping = published.get((port, protocol))
            if problems.check(mapping is not None, f"{where}: {name}: {section}.port "
                              f"{port}/{protocol} is not published"):
                problems.check(mapping[0] == port, f"{where}: {name}: {section} port {port} "
                               f"published as {mapping[0]}; clients are told {port}")
        admin = published.get((config["admin"]["port"], "tcp"))
        problems.check(admin is None or admin[1] == ["127.0.0.1"],
                       f"{where}: {name}: the admin port is published beyond 127.0.0.1")
        token = mounts.get(config["admin"]["token_file"])
        problems.check(token is not None and token.is_file(),
                       f"{where}: {name}: admin.token_file {config['admin']['token_file']} is "
                       "no mounted file")
        data_dir = config["server"]["data_dir"]
        problems.check(any(data_dir == m or data_dir.startswith(m.rstrip("/") + "/") for m in
                           [v.split(":")[1] for v in service.get("volumes", [])]),
                       f"{where}: {name}: server.data_dir {data_dir} is on no volume")
        outbox = [v.split(":")[0] for v in service.get("volumes", [])
                  if v.split(":")[1] == outbox_path(config)]
        if problems.check(len(outbox) == 1, f"{where}: {name}: db.outbox_dir "
                          f"{outbox_path(config)} is not a volume of its own"):
            outboxes.add(outbox[0])
        db_url = flag_value(args, "--db-url") or ""
        problems.check(re.match(r"postgresql://[^@/]*@postgres:5432/", db_url) is not None,
                       f"{where}: {name}: --db-url {db_url!r} is not the postgres service")
        problems.check("postgres" in service.get("depends_on", {}),
                       f"{where}: {name}: does not wait for postgres")
    problems.check(len(servers) == 2, f"{where}: two servers expected, found {sorted(servers)}")
    problems.check(len(outboxes) == 1 and next(iter(outboxes)) in compose.get("volumes", {}),
                   f"{where}: the servers' outboxes must be one named volume, as the Fleet's "
                   f"share one claim; found {sorted(outboxes)}")
    ports = [(c["control"]["port"], c["game"]["port"]) for c in servers.values()]
    problems.check(len(set(ports)) == len(ports), f"{where}: servers share ports {ports}")

    prometheus = services.get("prometheus", {})
    problems.check("./prometheus:/etc/prometheus:ro" in prometheus.get("volumes", []),
                   f"{where}: prometheus must mount ./prometheus at /etc/prometheus")
    config = load_yaml(deploy / "prometheus/prometheus.yml")
    jobs = config["scrape_configs"]
    targets = {target for job in jobs for static in job.get("static_configs", [])
               for target in static["targets"]}
    wanted = {f"{name}:{c['admin']['port']}" for name, c in servers.items()}
    problems.check(targets == wanted, f"prometheus.yml: targets {sorted(targets)}, the servers' "
                   f"admin ports are {sorted(wanted)}")
    for job in jobs:
        credentials = job.get("authorization", {}).get("credentials_file")
        problems.check(credentials is not None and
                       (deploy / "prometheus" / credentials).resolve() in
                       {(deploy / "prometheus/admin-token").resolve()},
                       f"prometheus.yml: job {job['job_name']}: the bearer token must be the "
                       "servers' admin-token file")
    problems.check(config.get("rule_files") == ["alerts.yml"],
                   "prometheus.yml: rule_files must be alerts.yml")


def check_manifests(source, binary):
    problems = Problems()
    server = Server(binary)
    base = Kustomization(source / "deploy/kubernetes/base")
    result = check_fleet(base, source, server, problems)
    fleet_name = result[0]["metadata"]["name"] if result else None
    autoscaler = only(base.of_kind("FleetAutoscaler"), "FleetAutoscaler in the base", problems)
    if autoscaler is not None:
        check_autoscaler(autoscaler, fleet_name, problems, "fleetautoscaler.yaml")
    if result:
        check_tick_budget_alert(source, result[1], problems)
    check_overlay(Kustomization(source / "deploy/kubernetes/overlays/example"), base, problems)
    check_compose(source, server, problems)
    return problems


# ------------------------------------------------------------------------------------ rendered

def check_rendered(directory, kubectl, problems, overlay):
    run = subprocess.run([kubectl, "kustomize", str(directory)], capture_output=True, text=True,
                         timeout=60)
    where = f"kubectl kustomize {directory}"
    if not problems.check(run.returncode == 0, f"{where}: exit {run.returncode}: {run.stderr}"):
        return
    documents = [doc for doc in yaml.safe_load_all(run.stdout) if doc]
    names = {}
    for doc in documents:
        names.setdefault(doc["kind"], set()).add(doc["metadata"]["name"])
        labels = doc["metadata"].get("labels", {})
        if doc["kind"] != "Namespace":
            problems.check(labels.get("app.kubernetes.io/name") == "ricochet",
                           f"{where}: {doc['kind']} {doc['metadata']['name']} lacks "
                           "app.kubernetes.io/name=ricochet")
            if overlay:
                problems.check(doc["metadata"].get("namespace") == overlay,
                               f"{where}: {doc['kind']} {doc['metadata']['name']} is not in "
                               f"namespace {overlay}")
    for doc in documents:
        if doc["kind"] == "Fleet":
            pod = doc["spec"]["template"]["spec"]["template"]["spec"]
            for volume in pod.get("volumes", []):
                if "configMap" in volume:
                    problems.check(volume["configMap"]["name"] in names.get("ConfigMap", ()),
                                   f"{where}: volume {volume['name']} names no rendered ConfigMap")
                if "secret" in volume:
                    problems.check(volume["secret"]["secretName"] in names.get("Secret", ()),
                                   f"{where}: volume {volume['name']} names no rendered Secret")
                if "persistentVolumeClaim" in volume:
                    problems.check(volume["persistentVolumeClaim"]["claimName"] in
                                   names.get("PersistentVolumeClaim", ()),
                                   f"{where}: volume {volume['name']} names no rendered "
                                   "PersistentVolumeClaim")
            for container in pod["containers"]:
                for env in container.get("env", []):
                    ref = env.get("valueFrom", {}).get("secretKeyRef")
                    if ref:
                        problems.check(ref["name"] in names.get("Secret", ()),
                                       f"{where}: env {env['name']} names no rendered Secret")
                if overlay:
                    problems.check(container["image"] != "ricochet",
                                   f"{where}: the overlay names no image")
        if doc["kind"] == "FleetAutoscaler":
            problems.check(doc["spec"]["fleetName"] in names.get("Fleet", ()),
                           f"{where}: fleetName {doc['spec']['fleetName']} is no rendered Fleet")
        if doc["kind"] == "PodMonitor":
            for endpoint in doc["spec"]["podMetricsEndpoints"]:
                name = endpoint["authorization"]["credentials"]["name"]
                problems.check(name in names.get("Secret", ()),
                               f"{where}: PodMonitor credentials name no rendered Secret")
    problems.check({"Fleet", "FleetAutoscaler", "ConfigMap", "Secret", "PodMonitor",
                    "PersistentVolumeClaim"} <=
                   set(names), f"{where}: rendered kinds {sorted(names)}")


def check_render(source):
    kubectl = shutil.which("kubectl")
    if kubectl is None:
        print("kubectl is not installed (it is not in Debian): rendering skipped")
        return None
    problems = Problems()
    check_rendered(source / "deploy/kubernetes/base", kubectl, problems, None)
    overlay_dir = source / "deploy/kubernetes/overlays/example"
    namespace = load_yaml(overlay_dir / "kustomization.yaml")["namespace"]
    check_rendered(overlay_dir, kubectl, problems, namespace)
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mode", choices=["manifests", "render"])
    parser.add_argument("--source", required=True, type=Path, help="the repository's root")
    parser.add_argument("--server", help="the ricochet-server binary (manifests)")
    options = parser.parse_args()
    if options.mode == "manifests":
        if not options.server or not os.access(options.server, os.X_OK):
            print(f"no ricochet-server binary at {options.server}; build it first")
            return 1
        problems = check_manifests(options.source.resolve(), options.server)
    else:
        problems = check_render(options.source.resolve())
        if problems is None:
            return SKIPPED
    for problem in problems.items:
        print(f"problem: {problem}")
    print(f"{len(problems.items)} problem(s)")
    return 1 if problems.items else 0


if __name__ == "__main__":
    sys.exit(main())
