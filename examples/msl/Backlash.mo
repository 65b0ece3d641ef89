within Modelica.Mechanics.Rotational.Examples;
model Backlash "Example to demonstrate backlash"
  extends Modelica.Icons.Example;
  Components.Fixed fixed1(phi0=0.0);
  Components.SpringDamper springDamper(c=20000.0, d=50.0);
  Components.Inertia inertia1(J=5.0, phi(start=1.570796326794897, fixed=true), w(start=0.0, fixed=true));
  Components.Fixed fixed2(phi0=0.0);
  Components.ElastoBacklash elastoBacklash(c=20000.0, d=50.0, b=0.7853981633974483);
  Components.Inertia inertia2(J=5.0, phi(start=1.570796326794897, fixed=true), w(start=0.0, fixed=true));
  Components.Fixed fixed3(phi0=0.0);
  Components.ElastoBacklash2 elastoBacklash2(c=20000.0, d=50.0, b=0.78539816339745);
  Components.Inertia inertia3(J=5.0, phi(start=1.570796326794897, fixed=true), w(start=0.0, fixed=true));
equation
  connect(fixed1.flange, springDamper.flange_a);
  connect(springDamper.flange_b, inertia1.flange_a);
  connect(fixed2.flange, elastoBacklash.flange_a);
  connect(elastoBacklash.flange_b, inertia2.flange_a);
  connect(fixed3.flange, elastoBacklash2.flange_a);
  connect(elastoBacklash2.flange_b, inertia3.flange_a);
  annotation(experiment(StopTime=1.0, Interval=0.001, Tolerance=1e-06));
end Backlash;
