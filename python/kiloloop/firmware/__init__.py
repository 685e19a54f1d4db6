"""The firmware path: `kiloloop export` (a robot and its controller settings as one C++ header)
and `kiloloop b2b` (a SIL run's controller inputs replayed through that header in the firmware
example, examples/firmware/, every output compared bit for bit). docs/firmware.md.

    families.py  which controller and SIL scenario each robot family's firmware runs
    recording.py a SIL run that logs every controller input and output (the b2b log)
    export.py    robot_export.hpp + manifest.json
    build.py     the -fno-exceptions -fno-rtti core install and the firmware build (CMake)
    b2b.py       all of it for one robot
"""
