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

# What the release binary needs at run time on a bare Debian (scripts/release-smoke checks
# it): TLS to a shared PostgreSQL store (OpenSSL), text in plots (fontconfig, freetype, a
# font) and the gamepad (libudev). The wheel bundles its own (auditwheel).
RUNTIME_PACKAGES=(libssl3 libfontconfig1 libfreetype6 fonts-dejavu-core libudev1)

# The tests of the shared store run a private PostgreSQL server (scripts/pg-test-server),
# with a throw-away certificate made by openssl; xdotool types on the control window;
# Debian's old MuJoCo 2.2.2 is the "wrong version" proleg must refuse; iproute2 and iptables
# make the hosts of the network tests (scripts/hosts: namespaces, cut links, lost packets);
# the dashboard's tests drive Chromium through chromedriver; g++ compiles libFuzzer for the
# fuzz targets (scripts/fuzz).
TEST_PACKAGES=(g++ postgresql openssl python3 python3-venv xdotool libmujoco2.2.2 iproute2 iptables chromium chromium-driver)

# From the Python registry: peer checks (URDFs we did not write, pybullet's pybullet_data,
# for the import tests; MuJoCo for the cross-engine check of an exported gait and the
# plain Gymnasium environment `python -m proleg.bench` compares with), and what the Python
# package `proleg` (python/) is built and tested with: maturin, Gymnasium, pandas, pytest.
PYTHON_PACKAGES=(pybullet==3.2.7 mujoco==4.0.0 maturin==1.16.0 "gymnasium[mujoco]==1.4.0" pandas==3.1.1 pytest==9.2.0 safetensors==0.8.0)

# A virtual environment with PYTHON_PACKAGES under ~/.cache/proleg/python (made once, topped
# up when the list grows); exports PROLEG_PYTHON, its interpreter, for the tests.
ensure_python() {
  local venv="$HOME/.cache/proleg/python"
  if ! "$venv/bin/python" -c "import mujoco, pybullet_data, gymnasium, imageio, pandas, pytest, maturin, safetensors" >/dev/null 2>&1; then
    echo "installing into $venv: ${PYTHON_PACKAGES[*]}"
    [ -x "$venv/bin/python" ] || python3 -m venv "$venv"
    "$venv/bin/pip" install -q "${PYTHON_PACKAGES[@]}"
  fi
  export PROLEG_PYTHON="$venv/bin/python"
}

# Builds and installs the Python package `proleg` from python/ into PROLEG_PYTHON's
# environment, as `pip install ./python` does (maturin builds the extension in release with
# cargo, into CARGO_TARGET_DIR when set; build isolation off: maturin is the venv's, on the
# PATH for pip's build hook).
install_python_package() {
  PATH="$(dirname "$PROLEG_PYTHON"):$PATH" "$PROLEG_PYTHON" -m pip install -q --no-build-isolation ./python
}

# The control window: gamepad support builds against libudev; GUI tests render under Xvfb
# with Mesa's software Vulkan (llvmpipe); videos are encoded (and tested) by ffmpeg.
GUI_PACKAGES=(libudev-dev xvfb xauth mesa-vulkan-drivers libvulkan1 ffmpeg)

# MuJoCo, the second physics engine (`--engine mujoco`): its C library and headers from the
# Python registry's mujoco-core wheel, unpacked under ~/.local/share/proleg/mujoco (lib/,
# include/). PROLEG_MUJOCO overrides where proleg looks for the library (a file or a folder).
MUJOCO_VERSION=4.0.0
ensure_mujoco() {
  local dir="${PROLEG_MUJOCO_DIR:-$HOME/.local/share/proleg/mujoco}"
  if [ ! -f "$dir/lib/libmujoco.so.$MUJOCO_VERSION" ]; then
    echo "installing MuJoCo $MUJOCO_VERSION (mujoco-core) into $dir"
    local tmp
    tmp=$(mktemp -d)
    python3 -m pip download -q --no-deps --only-binary=:all: -d "$tmp" "mujoco-core==$MUJOCO_VERSION"
    python3 - "$tmp" "$dir" "$MUJOCO_VERSION" <<'PY'
import glob, os, shutil, sys, zipfile
tmp, dest, version = sys.argv[1:]
wheel = glob.glob(os.path.join(tmp, "mujoco_core-*.whl"))[0]
lib, inc = os.path.join(dest, "lib"), os.path.join(dest, "include")
shutil.rmtree(dest, ignore_errors=True)
os.makedirs(lib)
with zipfile.ZipFile(wheel) as z:
    for name in z.namelist():
        if name == f"mujoco/libmujoco.so.{version}":
            with z.open(name) as src, open(os.path.join(lib, os.path.basename(name)), "wb") as dst:
                shutil.copyfileobj(src, dst)
        elif name.startswith("mujoco/include/") and not name.endswith("/"):
            path = os.path.join(inc, name[len("mujoco/include/"):])
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with z.open(name) as src, open(path, "wb") as dst:
                shutil.copyfileobj(src, dst)
PY
    rm -rf "$tmp"
  fi
  export PROLEG_MUJOCO_DIR="$dir"
  export PROLEG_MUJOCO="${PROLEG_MUJOCO:-$dir/lib/libmujoco.so.$MUJOCO_VERSION}"
}
