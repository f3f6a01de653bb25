"""The robot runtime: ARMAR-III in MuJoCo with placo whole-body IK (optional extra ``robot``)."""
