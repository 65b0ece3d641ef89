within Modelica.Mechanics.Rotational.Examples;
model SimpleGearShift "Simple Gearshift"
  extends Modelica.Icons.Example;
  output SI.AngularVelocity wEngine=engine.w "Speed of engine";
  output SI.AngularVelocity wLoad=load.w "Speed of load";
  output Real gearRatio=wLoad/max(wEngine, 1e-6) "Gear ratio load/engine";

  Rotational.Sources.TorqueStep torqueStep(
    offsetTorque=0,
    startTime=0.5,
    stepTorque=20)
    annotation (Placement(transformation(extent={{-90,-10},{-70,10}})));
  Rotational.Components.Inertia engine(J=1)
    annotation (Placement(transformation(extent={{-60,-10},{-40,10}})));
  Rotational.Components.IdealPlanetary idealPlanetary(ratio=75/50)
    annotation (Placement(transformation(extent={{-10,-10},{10,10}})));
  Rotational.Components.Inertia load(
    J=10,
    phi(start=0, fixed=true),
    w(start=0, fixed=true))
    annotation (Placement(transformation(extent={{40,-10},{60,10}})));
  Rotational.Sources.QuadraticSpeedDependentTorque quadraticSpeedDependentTorque(
    w_nominal(displayUnit="rpm")=10.471975511966,
    tau_nominal=-20)
    annotation (Placement(transformation(extent={{90,-10},{70,10}})));
  Rotational.Components.Clutch clutch(
    cgeo=2,
    fn_max=100,
    phi_rel(fixed=true),
    w_rel(fixed=true))
    annotation (Placement(transformation(extent={{-10,-40},{10,-20}})));
  Rotational.Components.Brake brake(cgeo=2, fn_max=100)
    annotation (Placement(transformation(extent={{30,-40},{50,-20}})));
  Modelica.Blocks.Math.Feedback feedback
    annotation (Placement(transformation(extent={{20,30},{40,50}})));
  Modelica.Blocks.Sources.Constant const1(k=1)
    annotation (Placement(transformation(extent={{-10,30},{10,50}})));
  Modelica.Blocks.Sources.Ramp ramp(
    height=1,
    offset=0,
    startTime=2,
    duration=0.1)
    annotation (Placement(transformation(extent={{-40,50},{-20,70}})));
equation
  connect(torqueStep.flange, engine.flange_a) annotation (Line(points={{-70,0},{-60,0}}));
  connect(engine.flange_b, idealPlanetary.sun) annotation (Line(points={{-40,0},{-10,0}}));
  connect(engine.flange_b, clutch.flange_a) annotation (Line(points={{-40,0},{-20,0},{-20,-30},{-10,-30}}));
  connect(idealPlanetary.ring, clutch.flange_b) annotation (Line(points={{10,0},{20,0},{20,-30},{10,-30}}));
  connect(clutch.flange_b, brake.flange_a) annotation (Line(points={{10,-30},{30,-30}}));
  connect(idealPlanetary.carrier, load.flange_a) annotation (Line(points={{-10,4},{-14,4},{-14,20},{34,20},{34,0},{40,0}}));
  connect(quadraticSpeedDependentTorque.flange, load.flange_b) annotation (Line(points={{70,0},{60,0}}));
  connect(ramp.y, clutch.f_normalized) annotation (Line(points={{-19,60},{-16,60},{-16,-14},{0,-14},{0,-19}}, color={0,0,127}));
  connect(feedback.u2, clutch.f_normalized) annotation (Line(points={{30,48},{30,20},{0,20},{0,-19}}, color={0,0,127}));
  connect(const1.y, feedback.u1) annotation (Line(points={{11,40},{22,40}}, color={0,0,127}));
  connect(feedback.y, brake.f_normalized) annotation (Line(points={{39,40},{50,40},{50,-10},{40,-10},{40,-19}}, color={0,0,127}));
  annotation (experiment(StopTime=5, Interval=0.005, Tolerance=1e-06), Documentation(info="<html>
<p>This model shows a simple automatic gearshift. The gear shift is performed by a brake
holding the ring gear of a planetary gear and a clutch locking sun and ring gear.</p>
</html>"));
end SimpleGearShift;
