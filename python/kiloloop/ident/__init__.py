"""Identification of a robot's plant parameters from logs (`kiloloop excite`, `kiloloop identify`).

excite.py runs an excitation in the SIL and logs what a real robot's logger has; arm.py and
multirotor.py estimate, from such logs and the robot file as the nominal model only, what the
file's [sim.*] tables and scenario delays should say; patch.py writes the result as a robot file.
Layer: above scenarios/ and sil/ (it runs their rigs and reads their settings), below cli.py.
"""
