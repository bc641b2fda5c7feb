#!/usr/bin/env bash
# Gradescope runs this once when it builds the autograder's image (Ubuntu), in
# /autograder/source, where the uploaded zip is unpacked: this folder's files, raycast's source
# in raycast/ (a copy of this repository), and the course's suite in suite/ (COMMANDS.txt,
# scenes/, reference/, and POINTS for points other than one a picture). It builds raycast;
# run_autograder grades each submission with it.
set -euo pipefail
apt-get update -qq
apt-get install -y -qq build-essential curl python3
curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y --profile minimal
source "$HOME/.cargo/env"
cargo install --locked --path /autograder/source/raycast --root /usr/local
