#!/usr/bin/env bash
# Each bad input must end with a non-zero exit and a message naming what was wrong, never a crash.
set -u
mcvio=$1
domain=$((150 + RANDOM % 80))
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0
. "$(dirname "$0")/expect.sh"
printf '<dds><profiles><participant profile_name="x"><rtps>' > "$tmp/broken.xml"
expect 2 "$tmp/broken.xml" -- "$mcvio" --domain "$domain" --dds-profiles "$tmp/broken.xml" topics --wait 0.1
expect 2 "does not exist" -- "$mcvio" --domain "$domain" --dds-profiles "$tmp/missing.xml" topics --wait 0.1
expect 2 "invalid topic name '/bad topic'" -- "$mcvio" --domain "$domain" echo "/bad topic"
expect 2 "invalid topic name '/a//b'" -- "$mcvio" --domain "$domain" echo "/a//b"
expect 2 "domain id 233 is out of range" -- "$mcvio" --domain 233 topics
expect 2 "domain id -1 is out of range" -- "$mcvio" --domain -1 nodes
expect 2 "unknown type 'foo_msgs/msg/Bar'" -- "$mcvio" --domain "$domain" echo /imu0 --type foo_msgs/msg/Bar
expect 1 "no publisher of /nothing_here" -- "$mcvio" --domain "$domain" echo /nothing_here --timeout 1
expect 2 "unknown command 'no_such_command' (commands: topics" -- "$mcvio" no_such_command
expect 2 "unknown command 'no_such_command'" -- "$mcvio" --domain "$domain" no_such_command
expect 106 "A subcommand is required" -- "$mcvio" --domain "$domain"
expect 105 "--log-level: loud not in {trace,debug,info,warn,error,off}" -- "$mcvio" --log-level loud topics --wait 0.1
# Global options may follow the command too.
expect 105 "--log-level: loud not in {trace,debug,info,warn,error,off}" -- "$mcvio" topics --wait 0.1 --log-level loud
expect 2 "domain id 300 is out of range" -- "$mcvio" topics --wait 0.1 --domain 300
expect 2 "MCVIO_LOG_LEVEL: unknown level 'loud'" -- env MCVIO_LOG_LEVEL=loud "$mcvio" --domain "$domain" topics --wait 0.1
touch "$tmp/a_file"
expect 2 "output folder '$tmp/a_file/out': cannot create it" -- "$mcvio" run --dataset "$tmp/missing" --out "$tmp/a_file/out"
exit $failed
