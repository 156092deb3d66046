# The Python package kane_sim (src/kane_sim) for catkin_python_setup(): devel and install spaces
# put it beside the generated kane_sim.msg and the compiled kane_sim._core. Not for pip.
from setuptools import setup

from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["kane_sim", "kane_sim.identify"], package_dir={"": "src"}))
