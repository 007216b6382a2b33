"""``python -m proleg``: what the package is and where to start."""

from . import SCENARIOS, __version__

print(f"proleg {__version__}: registered Gymnasium ids")
for env_id, (file, what) in SCENARIOS.items():
    print(f"  {env_id:<24} {what} ({file})")
print("benchmark: python -m proleg.bench")
