"""Groups of simulate's CSV columns (which are also Result's and the plots' names), named once
for kane_sim.core's Result and kane_sim.plotting. No NumPy, no core: plot_bag imports it too."""

ENERGIES = ("kinetic", "gravitational", "spring", "energy")
LEDGER = ("motor_work", "dissipated_energy", "energy_balance", "impact_energy")
# The reaction forces (Kane's method, auxiliary speeds) [N], frame (0).
REACTIONS = ("pin_o_x", "pin_o_y", "pin_a_x", "pin_a_y", "pin_b_x", "pin_b_y", "rail_slider3",
             "rail_slider4", "spring_force")
# Each load's power [W] by short name: their sum is dT/dt.
POWERS = (("motor", "motor_power"), ("gravity", "power_gravity"), ("spring", "power_spring"),
          ("crank_damper", "power_crank_damper"), ("coupler_damper", "power_coupler_damper"),
          ("slider3_damper", "power_slider3_damper"), ("slider4_damper", "power_slider4_damper"),
          ("contact", "power_contact"))
# Each body's kinetic energy [J] by body.
KINETIC_PER_BODY = (("rod1", "kinetic_rod1"), ("rod2", "kinetic_rod2"),
                    ("slider3", "kinetic_slider3"), ("slider4", "kinetic_slider4"))
