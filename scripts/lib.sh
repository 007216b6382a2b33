# Shared helpers for proleg's scripts (sourced, not run).

# Installs the Debian packages given as arguments that are not installed yet.
ensure_packages() {
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "installing: ${missing[*]}"
    local sudo=""
    [ "$(id -u)" -ne 0 ] && sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
  fi
}

# Makes sure cargo (with rustfmt and clippy) is there.
ensure_rust() {
  if ! command -v cargo >/dev/null 2>&1; then
    [ -f "$HOME/.cargo/env" ] && . "$HOME/.cargo/env"
  fi
  command -v cargo >/dev/null 2>&1 || { echo "cargo not found: install Rust 1.95 (rustup)" >&2; exit 1; }
  if command -v rustup >/dev/null 2>&1; then
    rustup component list --installed 2>/dev/null | grep -q rustfmt || rustup component add rustfmt
    rustup component list --installed 2>/dev/null | grep -q clippy || rustup component add clippy
  fi
}

# Build dependencies of the headless core (C compiler and pkg-config for -sys crates;
# fontconfig and freetype for the plot text, with a font to draw it; OpenSSL for TLS to a
# shared PostgreSQL store).
HEADLESS_PACKAGES=(pkg-config gcc libfontconfig1-dev libfreetype-dev fonts-dejavu-core libssl-dev)

# The tests of the shared store run a private PostgreSQL server (scripts/pg-test-server),
# with a throw-away certificate made by openssl; xdotool types on the control window.
TEST_PACKAGES=(postgresql openssl python3 python3-venv xdotool)

# Peer checks from the Python registry: URDFs we did not write (pybullet's pybullet_data)
# for the import tests, and MuJoCo for the cross-engine check of an exported gait.
PYTHON_PACKAGES=(pybullet==3.2.7 mujoco==4.0.0)

# A virtual environment with PYTHON_PACKAGES under ~/.cache/proleg/python (made once);
# exports PROLEG_PYTHON, its interpreter, for the tests.
ensure_python() {
  local venv="$HOME/.cache/proleg/python"
  if ! "$venv/bin/python" -c "import mujoco, pybullet_data" >/dev/null 2>&1; then
    echo "installing into $venv: ${PYTHON_PACKAGES[*]}"
    python3 -m venv "$venv"
    "$venv/bin/pip" install -q "${PYTHON_PACKAGES[@]}"
  fi
  export PROLEG_PYTHON="$venv/bin/python"
}

# The control window: gamepad support builds against libudev; GUI tests render under Xvfb
# with Mesa's software Vulkan (llvmpipe); videos are encoded (and tested) by ffmpeg.
GUI_PACKAGES=(libudev-dev xvfb xauth mesa-vulkan-drivers libvulkan1 ffmpeg)
