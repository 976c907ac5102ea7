"""The paper's direct shear tests (section 4) on the block engine: the box, its tests, the calibration."""
