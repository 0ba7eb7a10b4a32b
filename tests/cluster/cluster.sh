#!/usr/bin/env bash
# A ClickHouse cluster one command away: 2 shards x 2 replicas of Debian's clickhouse-server (18.16) and one
# ZooKeeper (Debian's `zookeeper`, 3.8), every process our own, with its pid file, config, data and log
# under one folder.
#
#   tests/cluster/cluster.sh up      start what is not running, wait until every node answers and
#                                    system.clusters shows the topology, print the --store URL
#   tests/cluster/cluster.sh down    stop the processes named by the pid files (only those), keep the data
#   tests/cluster/cluster.sh status  one line per process
#   tests/cluster/cluster.sh url     the --store URL
#   tests/cluster/cluster.sh start-node K / stop-node K   one ClickHouse node (0..3) alone (fault tests)
#   tests/cluster/cluster.sh node K  write node K's config and run it in the foreground (K = zk or 0..3;
#                                    docker/compose.cluster.yaml runs every service so, one per host)
#
# Environment: CLUSTER_DIR (default build/cluster), CLUSTER_PORT (default 29100: ZooKeeper's client port;
# node K listens on HTTP CLUSTER_PORT+10+10K, native TCP +1, replication +2), CLUSTER_NAME (trailscope),
# CLUSTER_DB (trailscope), CLUSTER_HOSTS ("zk n0 n1 n2 n3": host names of ZooKeeper and the 4 nodes; all
# 127.0.0.1 by default), CLUSTER_FRESH=1 (up: delete the folder's data first), CLUSTER_DDL_TIMEOUT (seconds an
# ON CLUSTER query waits for every node, default 60; the query runs on a node that was down when it returns).
#
# Node K is shard K/2+1, replica K%2+1. Memory is kept small so that the 4 servers fit beside builds on a
# 24 GB machine: 64 MiB mark and uncompressed caches, 2 GB per query, 3 GB for all queries of a server,
# 4 background merge threads, a 256 MiB ZooKeeper heap.
set -euo pipefail

CLUSTER_DIR=${CLUSTER_DIR:-build/cluster}
CLUSTER_PORT=${CLUSTER_PORT:-29100}
CLUSTER_NAME=${CLUSTER_NAME:-trailscope}
CLUSTER_DB=${CLUSTER_DB:-trailscope}
read -r -a HOSTS <<<"${CLUSTER_HOSTS:-127.0.0.1 127.0.0.1 127.0.0.1 127.0.0.1 127.0.0.1}"
CLICKHOUSE_SERVER=${CLICKHOUSE_SERVER:-$(command -v clickhouse-server || echo /usr/sbin/clickhouse-server)}
ZK_CLASSPATH=${ZK_CLASSPATH:-/usr/share/java/zookeeper.jar}
NODES=(0 1 2 3)

mkdir -p "$CLUSTER_DIR"
CLUSTER_DIR=$(cd "$CLUSTER_DIR" && pwd)

zk_host() { echo "${HOSTS[0]}"; }
node_host() { echo "${HOSTS[$((1 + $1))]}"; }
http_port() { echo $((CLUSTER_PORT + 10 + 10 * $1)); }
tcp_port() { echo $((CLUSTER_PORT + 11 + 10 * $1)); }
repl_port() { echo $((CLUSTER_PORT + 12 + 10 * $1)); }

store_url() {
  local hosts=() k
  for k in "${NODES[@]}"; do hosts+=("$(node_host "$k"):$(http_port "$k")"); done
  local IFS=,
  echo "clickhouse://${hosts[*]}/${CLUSTER_DB}?cluster=${CLUSTER_NAME}"
}

write_zk_config() {
  local d=$CLUSTER_DIR/zk
  mkdir -p "$d/data"
  cat >"$d/zoo.cfg" <<EOF
tickTime=2000
initLimit=10
syncLimit=5
dataDir=$d/data
clientPort=$CLUSTER_PORT
# The admin server (Jetty) would listen on 8080 by default: not wanted here.
admin.enableServer=false
4lw.commands.whitelist=ruok,srvr
autopurge.snapRetainCount=3
autopurge.purgeInterval=1
EOF
}

write_node_config() {
  local k=$1 d=$CLUSTER_DIR/node$1 shard=$(($1 / 2 + 1)) replica=$(($1 % 2 + 1)) s r
  mkdir -p "$d/data" "$d/tmp" "$d/user_files" "$d/format_schemas"
  local listen=127.0.0.1
  [ "$(node_host "$k")" = 127.0.0.1 ] || listen=0.0.0.0
  {
    cat <<EOF
<?xml version="1.0"?>
<yandex>
  <logger><level>warning</level><log>$d/server.log</log><errorlog>$d/server.err.log</errorlog>
    <size>100M</size><count>2</count></logger>
  <http_port>$(http_port "$k")</http_port>
  <tcp_port>$(tcp_port "$k")</tcp_port>
  <interserver_http_port>$(repl_port "$k")</interserver_http_port>
  <interserver_http_host>$(node_host "$k")</interserver_http_host>
  <listen_host>$listen</listen_host>
  <max_connections>1024</max_connections>
  <keep_alive_timeout>10</keep_alive_timeout>
  <max_concurrent_queries>64</max_concurrent_queries>
  <uncompressed_cache_size>67108864</uncompressed_cache_size>
  <mark_cache_size>67108864</mark_cache_size>
  <path>$d/data/</path>
  <tmp_path>$d/tmp/</tmp_path>
  <user_files_path>$d/user_files/</user_files_path>
  <format_schema_path>$d/format_schemas/</format_schema_path>
  <users_config>$d/users.xml</users_config>
  <default_profile>default</default_profile>
  <default_database>default</default_database>
  <timezone>UTC</timezone>
  <mlock_executable>false</mlock_executable>
  <builtin_dictionaries_reload_interval>3600</builtin_dictionaries_reload_interval>
  <max_session_timeout>3600</max_session_timeout>
  <default_session_timeout>60</default_session_timeout>
  <distributed_ddl><path>/clickhouse/task_queue/ddl</path></distributed_ddl>
  <zookeeper><node><host>$(zk_host)</host><port>$CLUSTER_PORT</port></node>
    <session_timeout_ms>10000</session_timeout_ms></zookeeper>
  <macros><cluster>$CLUSTER_NAME</cluster><shard>$shard</shard><replica>r$replica</replica></macros>
  <remote_servers>
    <$CLUSTER_NAME>
EOF
    for s in 0 1; do
      echo "      <shard><internal_replication>true</internal_replication>"
      for r in 0 1; do
        echo "        <replica><host>$(node_host $((2 * s + r)))</host><port>$(tcp_port $((2 * s + r)))</port></replica>"
      done
      echo "      </shard>"
    done
    cat <<EOF
    </$CLUSTER_NAME>
  </remote_servers>
</yandex>
EOF
  } >"$d/config.xml"
  local net='<ip>::1</ip><ip>127.0.0.1</ip>'
  [ "$listen" = 127.0.0.1 ] || net='<ip>::/0</ip>'
  cat >"$d/users.xml" <<EOF
<?xml version="1.0"?>
<yandex>
  <profiles>
    <default>
      <max_memory_usage>2000000000</max_memory_usage>
      <max_memory_usage_for_all_queries>3000000000</max_memory_usage_for_all_queries>
      <max_threads>2</max_threads>
      <background_pool_size>4</background_pool_size>
      <use_uncompressed_cache>0</use_uncompressed_cache>
      <load_balancing>in_order</load_balancing>
      <distributed_ddl_task_timeout>${CLUSTER_DDL_TIMEOUT:-60}</distributed_ddl_task_timeout>
    </default>
  </profiles>
  <users>
    <default><password></password><networks>$net</networks><profile>default</profile><quota>default</quota></default>
  </users>
  <quotas><default><interval><duration>3600</duration><queries>0</queries><errors>0</errors>
    <result_rows>0</result_rows><read_rows>0</read_rows><execution_time>0</execution_time></interval></default></quotas>
</yandex>
EOF
}

alive() { [ -f "$1" ] && kill -0 "$(cat "$1")" 2>/dev/null; }


start_zk() {
  alive "$CLUSTER_DIR/zk/pid" && return 0
  write_zk_config
  # exec: $! is then the server's own pid, which `down` stops (not a subshell around it).
  (exec java -Xms64m -Xmx256m -cp "$CLUSTER_DIR/zk:$ZK_CLASSPATH" org.apache.zookeeper.server.ZooKeeperServerMain \
    "$CLUSTER_DIR/zk/zoo.cfg" >"$CLUSTER_DIR/zk/zk.log" 2>&1) &
  echo $! >"$CLUSTER_DIR/zk/pid"
}

start_node() {
  alive "$CLUSTER_DIR/node$1/pid" && return 0
  write_node_config "$1"
  (exec "$CLICKHOUSE_SERVER" --config-file="$CLUSTER_DIR/node$1/config.xml" >"$CLUSTER_DIR/node$1/stdout.log" 2>&1) &
  echo $! >"$CLUSTER_DIR/node$1/pid"
}

stop_pidfile() {
  local f=$1 pid i
  [ -f "$f" ] || return 0
  pid=$(cat "$f")
  if kill -0 "$pid" 2>/dev/null; then
    kill "$pid" 2>/dev/null || true
    for i in $(seq 1 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -0 "$pid" 2>/dev/null && kill -9 "$pid" 2>/dev/null || true
  fi
  rm -f "$f"
}

query() { # query K SQL: runs SQL on node K over HTTP, prints the answer
  curl -sS --max-time 10 "http://$(node_host "$1"):$(http_port "$1")/" --data-binary "$2"
}

zk_ok() { # `srvr` over the client port (bash's /dev/tcp): "Mode: standalone" once it serves sessions (`ruok`
  # answers earlier, while a session handshake still fails, and ClickHouse 18.16 can crash on that)
  local ans
  ans=$( (exec 3<>"/dev/tcp/$(zk_host)/$CLUSTER_PORT" && printf srvr >&3 && timeout 2 cat <&3) 2>/dev/null || true)
  [[ "$ans" == *"Mode: standalone"* ]]
}

wait_for() { # wait_for SECONDS WHAT CMD...
  local secs=$1 what=$2 i
  shift 2
  for i in $(seq 1 $((secs * 5))); do "$@" && return 0; sleep 0.2; done
  echo "cluster: $what not ready after ${secs}s (logs under $CLUSTER_DIR)" >&2
  return 1
}

node_ready() { # answers, sees the whole topology and reaches ZooKeeper
  [ "$(curl -sS --max-time 2 "http://$(node_host "$1"):$(http_port "$1")/ping" 2>/dev/null)" = Ok. ] || return 1
  [ "$(query "$1" "SELECT count() FROM system.clusters WHERE cluster = '$CLUSTER_NAME'" 2>/dev/null)" = 4 ] ||
    return 1
  query "$1" "SELECT count() FROM system.zookeeper WHERE path = '/'" >/dev/null 2>&1
}

up() {
  command -v "$CLICKHOUSE_SERVER" >/dev/null || { echo "cluster: clickhouse-server is not installed" >&2; exit 3; }
  [ -f "${ZK_CLASSPATH%%:*}" ] || { echo "cluster: ZooKeeper ($ZK_CLASSPATH) is not installed" >&2; exit 3; }
  if [ "${CLUSTER_FRESH:-0}" = 1 ]; then
    down
    rm -rf "${CLUSTER_DIR:?}"/zk "${CLUSTER_DIR:?}"/node?
  fi
  start_zk
  wait_for 60 "ZooKeeper (port $CLUSTER_PORT)" zk_ok
  local k
  for k in "${NODES[@]}"; do start_node "$k"; done
  for k in "${NODES[@]}"; do wait_for 90 "node $k (port $(http_port "$k"))" node_ready "$k"; done
  query 0 "CREATE DATABASE IF NOT EXISTS $CLUSTER_DB ON CLUSTER $CLUSTER_NAME" >/dev/null
  echo "cluster: 2 shards x 2 replicas + ZooKeeper under $CLUSTER_DIR"
  query 0 "SELECT shard_num, replica_num, host_address, port FROM system.clusters WHERE cluster = '$CLUSTER_NAME' \
ORDER BY shard_num, replica_num FORMAT TSV" | sed 's/^/  shard, replica, host, port: /'
  echo "--store $(store_url)"
}

down() {
  local k
  for k in "${NODES[@]}"; do stop_pidfile "$CLUSTER_DIR/node$k/pid"; done
  stop_pidfile "$CLUSTER_DIR/zk/pid"
}

status() {
  local k
  for f in zk node0 node1 node2 node3; do
    if alive "$CLUSTER_DIR/$f/pid"; then echo "$f running (pid $(cat "$CLUSTER_DIR/$f/pid"))"; else echo "$f stopped"; fi
  done
}

case "${1:-}" in
up) up ;;
down) down ;;
status) status ;;
url) store_url ;;
start-node)
  start_node "$2"
  wait_for 90 "node $2" node_ready "$2"
  ;;
stop-node) stop_pidfile "$CLUSTER_DIR/node$2/pid" ;;
kill-node) # SIGKILL: a crash, not a shutdown
  alive "$CLUSTER_DIR/node$2/pid" && kill -9 "$(cat "$CLUSTER_DIR/node$2/pid")"
  rm -f "$CLUSTER_DIR/node$2/pid"
  ;;
node)
  if [ "$2" = zk ]; then write_zk_config && exec java -Xms64m -Xmx256m -cp "$CLUSTER_DIR/zk:$ZK_CLASSPATH" \
    org.apache.zookeeper.server.ZooKeeperServerMain "$CLUSTER_DIR/zk/zoo.cfg"; fi
  write_node_config "$2"
  exec "$CLICKHOUSE_SERVER" --config-file="$CLUSTER_DIR/node$2/config.xml"
  ;;
*)
  echo "usage: $0 up | down | status | url | start-node K | stop-node K | kill-node K | node zk|K" >&2
  exit 2
  ;;
esac
