"""Package layout: ``components/`` and ``models/`` live at the repository root but install as
``flexlib.components`` and ``flexlib.models`` (metadata is in pyproject.toml)."""

from setuptools import find_packages, setup

packages = find_packages(include=["flexlib", "flexlib.*"])
package_dir = {"flexlib": "flexlib"}
for top in ("components", "models"):
    packages.append(f"flexlib.{top}")
    package_dir[f"flexlib.{top}"] = top
    packages += [f"flexlib.{top}.{sub}" for sub in find_packages(top)]
    package_dir.update({f"flexlib.{top}.{sub}": f"{top}/{sub.replace('.', '/')}" for sub in find_packages(top)})

setup(packages=packages, package_dir=package_dir)
