#!/usr/bin/env bash
# Makes sure the Apache Kafka broker's jars are in .cache/kafka/<version>/libs (fetched from
# Maven Central with Maven: org.apache.kafka:kafka_2.13 and its runtime dependencies, see
# scripts/kafka/pom.xml) and prints that folder. Quick when they are already there. The tests
# run the broker from it (tests/integration/_kafka.py): one KRaft node, no ZooKeeper.
#   scripts/ensure-kafka.sh            the default version
#   KAFKA_VERSION=4.0.0 scripts/ensure-kafka.sh
# Needs Java 17 or newer and Maven; says what to install when either is missing.
set -euo pipefail
version=${KAFKA_VERSION:-4.1.1}
java_needed=17
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
dest="$root/.cache/kafka/$version"

if [ -f "$dest/.complete" ]; then
  echo "$dest/libs"
  exit 0
fi

java_major() {
  # `java -version` prints e.g. 'openjdk version "17.0.15" 2025-04-15' (or "1.8.0_392") on stderr.
  java -version 2>&1 | awk -F'"' '/version/ {split($2, v, "."); print (v[1] == "1" ? v[2] : v[1]); exit}'
}
missing=()
if ! command -v java >/dev/null; then
  missing+=("Java $java_needed or newer (no java on PATH)")
elif [ "$(java_major)" -lt "$java_needed" ] 2>/dev/null || [ -z "$(java_major)" ]; then
  missing+=("Java $java_needed or newer (java on PATH is $(java -version 2>&1 | head -1))")
fi
command -v mvn >/dev/null || missing+=("Maven (no mvn on PATH)")
if [ ${#missing[@]} -gt 0 ]; then
  {
    echo "The Kafka tests run Apache Kafka $version from its Maven Central jars, which needs:"
    printf '  - %s\n' "${missing[@]}"
    echo "On Debian/Ubuntu: apt-get install openjdk-17-jre-headless maven"
  } >&2
  exit 1
fi

mkdir -p "$dest"
# Test runs side by side may both find the jars missing: one fetches, the other waits for it.
exec 9>"$dest/.lock"
flock 9
if [ -f "$dest/.complete" ]; then
  echo "$dest/libs"
  exit 0
fi
echo "Fetching the jars of Apache Kafka $version into $dest/libs ..." >&2
tmp="$dest/libs.tmp"
rm -rf "$tmp"
# The plugin's version is named: Maven's default for a bare `dependency:` differs by release.
if ! mvn -q -B -f "$here/kafka/pom.xml" -Dkafka.version="$version" \
    org.apache.maven.plugins:maven-dependency-plugin:3.8.1:copy-dependencies \
    -DincludeScope=runtime -DoutputDirectory="$tmp" >"$dest/mvn.log" 2>&1; then
  tail -20 "$dest/mvn.log" >&2
  echo "Maven could not fetch Apache Kafka $version (whole log: $dest/mvn.log)" >&2
  exit 1
fi
ls "$tmp"/kafka_2.13-"$version".jar >/dev/null
rm -rf "$dest/libs"
mv "$tmp" "$dest/libs"
touch "$dest/.complete"
echo "$dest/libs"
